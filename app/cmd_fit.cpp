// layerlab fit SCENE.json MEASUREMENTS.json --out CALIBRATED.json: the display
// as built, fitted with Ceres to what a camera at the eye measured
// (docs/measurements-format.md). Writes a scene file every other command
// reads unchanged, and prints the calibration report.
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <tuple>

#include "layerlab/app/command_result.h"
#include "layerlab/app/commands.h"
#include "layerlab/app/number_list.h"
#include "layerlab/calibration/calibrated_scene.h"
#include "layerlab/calibration/calibration.h"
#include "layerlab/calibration/fit_steps.h"
#include "layerlab/framework/atomic_file.h"
#include "layerlab/framework/params.h"
#include "layerlab/framework/staged_output.h"
#include "layerlab/framework/units.h"
#include "layerlab/framework/version.h"
#include "layerlab/systems/compile.h"

namespace layerlab::app {

namespace {

struct FitCommandOptions {
  std::string scene, measurements, out, report, loss = "none", axis = "camera", marker_loss_scale;
  std::string focal_length = ToString(CalibrationOptions().focal_length),
              lens_gaps = ToString(CalibrationOptions().lens_gaps),
              distortion = ToString(CalibrationOptions().distortion);
  std::optional<double> luminance_loss, model_error_level;  // unset: CalibrationOptions' own
  bool fit_focal_length = false, fit_lens_gaps = false, force = false, accept_model_error = false;
};

CalibrationOptions ReadCalibrationOptions(const FitCommandOptions& o) {
  CalibrationOptions options;
  try {
    options.loss = RobustLossFromString(o.loss);
    options.reference = AxisReferenceFromString(o.axis);
  } catch (const Error& e) {
    throw Error(std::string(o.loss == ToString(options.loss) ? "--axis: " : "--loss: ") + e.message());
  }
  for (const auto& [choice, text, flag, option] :
       {std::tuple{&options.focal_length, o.focal_length, o.fit_focal_length, "--focal-length"},
        std::tuple{&options.lens_gaps, o.lens_gaps, o.fit_lens_gaps, "--lens-gaps"},
        std::tuple{&options.distortion, o.distortion, false, "--distortion"}}) {
    try {
      *choice = flag ? FitChoice::kFit : FitChoiceFromString(text);
    } catch (const Error& e) {
      throw Error(std::string(option) + ": " + e.message());
    }
  }
  options.accept_model_error = o.accept_model_error;
  if (o.model_error_level) {
    if (!(*o.model_error_level > 0 && *o.model_error_level < 0.5))
      throw Error("--model-error-level: must lie in (0, 0.5), the probability that a right model is called wrong");
    options.model_error_level = *o.model_error_level;
  }
  // A value given must be positive (a negative one was ignored before).
  if (o.luminance_loss && !(*o.luminance_loss > 0 && std::isfinite(*o.luminance_loss)))
    throw Error("--luminance-loss-scale: must be positive");
  if (!o.marker_loss_scale.empty()) {
    const double arcmin = ParseOptionValue(o.marker_loss_scale, "--marker-loss-scale", kArcminutes);
    if (!(arcmin > 0)) throw Error("--marker-loss-scale: must be positive");
    options.marker_loss_scale_rad = arcmin / 60.0 * kRadiansPerDegree;
  }
  options.luminance_loss_scale = o.luminance_loss.value_or(options.luminance_loss_scale);
  return options;
}

// A fit that leaves parameters undetermined writes nothing unless --force.
void RefuseUnresolved(const FitCommandOptions& o, const CalibrationReport& report) {
  if (report.unresolved.empty()) return;
  const std::string what = "the data do not determine " + JoinWords(report.unresolved, "; and ") +
                           " (undetermined: a parameter at a bound of the model, or with a standard deviation "
                           "above " +
                           FormatFixed(100 * kUndeterminedStdDevFraction, 0) +
                           " % of its value; docs/measurements-format.md)";
  if (!o.force)
    throw Error(what +
                ". The calibrated scene was not written: add markers, captures or camera positions, or "
                "write it anyway with --force");
  std::cerr << "warning: " << what << "; --force: writing the calibrated scene anyway\n";
}

// The calibrated scene, which must compile before it replaces anything.
void WriteCalibratedScene(const FitCommandOptions& o, const CalibratedDisplay& display) {
  nlohmann::ordered_json calibrated = CalibratedSceneDocument(ReadDocumentInOrder(o.scene), o.scene, display);
  // Absolute: a bare file name has no parent folder to rebase from.
  RebaseRelativePaths(calibrated, std::filesystem::absolute(o.scene).string(),
                      std::filesystem::absolute(o.out).string());
  AtomicFile file(o.out);
  WriteFileAtomically(file.temp_path(), calibrated.dump(2) + "\n");
  try {
    Compile(LoadScene(file.temp_path()));
  } catch (const Error& e) {
    throw Error(o.out + ": the calibrated scene does not compile (" + e.message() + "); nothing was written");
  }
  file.Commit();
}

void RunFitCommand(const FitCommandOptions& o) {
  const std::vector<NamedInput> inputs = {{o.scene, "the scene"}, {o.measurements, "the measurements"}};
  RefuseOutputOverlappingInputs(o.out, inputs);
  if (!o.report.empty()) RefuseOutputOverlappingInputs(o.report, inputs);
  DisplaySystem system = Compile(LoadScene(o.scene));
  Measurements measurements = ReadMeasurementsFile(o.measurements);
  const CalibrationOptions options = ReadCalibrationOptions(o);

  CalibratedDisplay display;
  CalibrationReport report = Calibrate(system, measurements, options, &display);
  CommandResult result("fit");
  result.Text(report.FullReport());
  if (!o.report.empty()) {
    nlohmann::json j = report.ToJson();
    j["layerlab"] = VersionLine();
    WriteFileAtomically(o.report, j.dump(2) + "\n");
  }
  if (!report.IsSolutionUsable()) throw Error("the calibration failed: " + report.message + "; nothing was written");
  RefuseUnresolved(o, report);
  WriteCalibratedScene(o, display);
  result.Text("wrote " + o.out + (o.report.empty() ? "" : " and " + o.report) + "\n");
  result["out"] = o.out;
  result["calibration"] = report.ToJson();
  result.Print();
}

}  // namespace

void AddFitCommand(CLI::App& app) {
  auto o = std::make_shared<FitCommandOptions>();
  CLI::App* cmd = app.add_subcommand("fit", "Calibrate a scene from measurements of the built display (Ceres)");
  cmd->add_option("scene", o->scene, "Scene file as designed (JSON)")->required();
  cmd->add_option("measurements", o->measurements, "Measurements file (layerlab-measurements/1)")->required();
  cmd->add_option("--out", o->out, "Calibrated scene file to write")->required();
  cmd->add_option("--report", o->report, "Also write the report as JSON to this file");
  cmd->add_option("--loss", o->loss, "Robust loss against outliers: none, huber or cauchy");
  const CalibrationOptions defaults;  // the one home of the loss scales' defaults
  cmd->add_option("--marker-loss-scale", o->marker_loss_scale,
                  "Marker error where the robust loss starts to discount: arcmin, or with units (default " +
                      FormatFixed(ArcminFromRadians(defaults.marker_loss_scale_rad), 0) + " arcmin)");
  cmd->add_option("--luminance-loss-scale", o->luminance_loss,
                  "Luminance error, relative to the brightest reading, where the robust loss starts (default " +
                      FormatFixed(defaults.luminance_loss_scale, 2) + ")");
  cmd->add_option("--axis", o->axis,
                  "What defines the eye's axis: camera, or farthest-panel (centers the farthest "
                  "panel)");
  cmd->add_option("--focal-length", o->focal_length,
                  "The focal length of every lens and curved mirror: auto (fitted when captures from two or more "
                  "camera positions determine it, else held and said so), fit, or hold (default auto)");
  cmd->add_option("--lens-gaps", o->lens_gaps,
                  "The gap of every lens and curved mirror: auto, fit or hold, as --focal-length (it needs two or "
                  "more camera positions and two panels at different depths behind it; default auto)");
  cmd->add_option("--distortion", o->distortion,
                  "The radial distortion of every lens and curved mirror (reported, not written into the calibrated "
                  "scene): hold (at 0, default), fit, or auto (fitted wherever there are markers)");
  cmd->add_flag("--fit-focal-length", o->fit_focal_length, "Same as --focal-length fit");
  cmd->add_flag("--fit-lens-gaps", o->fit_lens_gaps, "Same as --lens-gaps fit");
  cmd->add_flag("--accept-model-error", o->accept_model_error,
                "Write the calibrated scene even when the markers' residual exceeds the noise measured in the "
                "photographs (a model error)");
  cmd->add_option(
      "--model-error-level", o->model_error_level,
      "Significance level of the model-error test (default " + FormatFixed(defaults.model_error_level, 3) + ")");
  cmd->add_flag("--force", o->force,
                "Write the calibrated scene even when the fit leaves a parameter undetermined (at a bound of the "
                "model, or a standard deviation above 10 % of its value)");
  cmd->callback([o] { RunFitCommand(*o); });
}

}  // namespace layerlab::app
