#include "layerlab/solvers/solution_writer.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "layerlab/framework/atomic_file.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/exr_image.h"
#include "layerlab/framework/lightfield_io.h"
#include "layerlab/framework/png_writer.h"
#include "layerlab/framework/progress.h"
#include "layerlab/framework/staged_output.h"
#include "layerlab/framework/version.h"
#include "layerlab/kernels/synthesis.h"
#include "layerlab/solvers/response_pass.h"
#include "layerlab/solvers/trace_columns.h"
#include "layerlab/systems/source_spread.h"
#include "layerlab/systems/system_report.h"

namespace layerlab {

namespace fs = std::filesystem;

std::vector<float> AsTheEyeSeesIt(const VirtualLayer& layer, const LayerPattern& t) {
  std::vector<float> eye(t.rgb.size());
  for (int row = 0; row < t.rows; ++row)
    for (int col = 0; col < t.cols; ++col) {
      const int from_col = layer.flip_x ? t.cols - 1 - col : col, from_row = layer.flip_y ? t.rows - 1 - row : row;
      for (int c = 0; c < 3; ++c)
        eye[(static_cast<size_t>(row) * t.cols + col) * 3 + c] =
            t.rgb[(static_cast<size_t>(from_row) * t.cols + from_col) * 3 + c];
    }
  return eye;
}

PanelEncoding EncodeForPanel(const VirtualLayer& layer, const LayerPattern& driven) {
  const bool leds = IsSolvedEmitter(layer);
  const LayerPattern values = leds ? LedValues(layer, driven) : LayerPattern{};
  const LayerPattern& pattern = leds ? values : driven;
  const PanelSpec& panel = layer.panel;
  PanelEncoding out;
  out.cols = leds ? pattern.cols : static_cast<int>(panel.resolution_cols);
  out.rows = leds ? pattern.rows : static_cast<int>(panel.resolution_rows);
  out.active_cols = pattern.cols, out.active_rows = pattern.rows;
  out.active_left = leds ? 0 : static_cast<int>(panel.active_left);
  out.active_top = leds ? 0 : static_cast<int>(panel.active_top);
  out.pixels.assign(static_cast<size_t>(out.cols) * out.rows * 3, 0);
  const double black = panel.black_level, inverse_gamma = 1.0 / panel.gamma;
  for (int row = 0; row < pattern.rows; ++row)
    for (int col = 0; col < pattern.cols; ++col)
      for (int c = 0; c < 3; ++c) {
        double t = pattern.rgb[(static_cast<size_t>(row) * pattern.cols + col) * 3 + c];
        double drive = (t - black) / (1.0 - black);
        if (drive < 0) ++out.below_black_level, drive = 0;
        double code = std::round(255.0 * std::pow(std::min(drive, 1.0), inverse_gamma));
        size_t at = ((static_cast<size_t>(row) + out.active_top) * out.cols + col + out.active_left) * 3 + c;
        out.pixels[at] = static_cast<uint8_t>(code);
      }
  return out;
}

nlohmann::json ReportSummaryJson(const SolverReport& r) {
  nlohmann::json j = {{"solver", r.solver},
                      {"termination", ToString(r.termination)},
                      {"message", r.message},
                      {"usable", r.IsSolutionUsable()},
                      {"iterations", r.iterations},
                      {"seconds", r.seconds},
                      {"setup_seconds", r.setup_seconds},
                      {"rays", r.rays},
                      {"threads", r.threads},
                      {"threads_min", r.threads_min},
                      {"initial_objective", r.initial_objective},
                      {"final_objective", r.final_objective},
                      {"final_psnr_db", JsonNumber(r.final_psnr_db)},
                      {"target_out_of_range", r.out_of_range},
                      {"target_scale", r.target_scale},
                      {"warnings", r.warnings},
                      {"brief", r.BriefReport()},
                      {"layerlab", VersionLine()}};
  j["objective"] = r.objective;
  const bool focal_stack = std::any_of(r.trace.begin(), r.trace.end(),
                                       [](const IterationRecord& t) { return !std::isnan(t.focal_stack_psnr_db); });
  if (focal_stack) j["retinal_target"] = r.retinal_target;
  if (r.objective == "retinal") j["contrast_sensitivity"] = r.contrast_sensitivity;
  if (r.panel_diffraction) j["panel_diffraction"] = true;
  if (r.lc_response) j["lc_response"] = true;
  if (!std::isnan(r.shown_psnr_db)) j["shown_psnr_db"] = JsonNumber(r.shown_psnr_db);
  if (r.flicker) j["flicker"] = r.flicker->ToJson();
  if (focal_stack) j["pupil_positions"] = r.pupil_positions;
  return j;
}

nlohmann::json ReportToJson(const SolverReport& r) {
  nlohmann::json j = ReportSummaryJson(r);
  const std::vector<const TraceColumn*> columns = WrittenColumns(r.trace);
  for (const IterationRecord& t : r.trace) {
    nlohmann::json row;
    for (const TraceColumn* c : columns) row[c->name] = TraceJson(*c, t);
    j["trace"].push_back(std::move(row));
  }
  return j;
}

std::string TraceCsv(const SolverReport& report) {
  // A trace that measured the focal stack (the retinal objective's, or measure_focal_stack) also has its PSNR.
  const std::vector<const TraceColumn*> columns = WrittenColumns(report.trace);
  std::string csv;
  for (const TraceColumn* c : columns) csv += std::string(csv.empty() ? "" : ",") + c->name;
  csv += "\n";
  for (const IterationRecord& r : report.trace)
    for (size_t k = 0; k < columns.size(); ++k)
      csv += TraceField(*columns[k], columns[k]->value(r)) + (k + 1 < columns.size() ? "," : "\n");
  return csv;
}

namespace {
std::string PatternFile(const std::string& folder, const VirtualLayer& layer) {
  return (fs::path(folder) / "patterns" / (layer.name + ".exr")).string();
}
}  // namespace

void CheckTransmittance(const LayerPattern& p, const std::string& what) {
  const std::vector<std::string> channels = {"R", "G", "B"};
  const size_t values = p.pixel_count() * 3;
  if (p.rgb.size() != values) throw Error(what + ": internal error: a pattern's buffer does not match its size");
  std::string why = FindValueThatIsNotLight(p.rgb.data(), values, p.cols, channels);
  for (size_t k = 0; why.empty() && k < values; ++k) {
    if (p.rgb[k] <= 1.0f) continue;
    const size_t pixel = k / 3;
    why = "pixel (row " + std::to_string(pixel / p.cols) + ", col " + std::to_string(pixel % p.cols) + ") channel " +
          channels[k % 3] + " is " + std::to_string(p.rgb[k]) + "; a transmittance is in [0, 1]";
  }
  if (!why.empty()) throw Error(what + ": " + why);
}

Patterns ReadPatterns(const DisplayModel& model, const std::string& folder) {
  for (const std::string& line : FinishPendingSwitchOvers(folder)) Note(line);
  Patterns t;
  for (size_t k = 0; k < model.layer_count(); ++k) {
    const VirtualLayer& layer = model.system().layers[k];
    std::string file = PatternFile(folder, layer);
    Image image = ReadExr(file, {"R", "G", "B"});
    if (image.width != layer.cols || image.height != layer.rows)
      throw Error(file + ": is " + std::to_string(image.width) + " x " + std::to_string(image.height) +
                  " pixels; layer \"" + layer.name + "\" has " + std::to_string(layer.cols) + " x " +
                  std::to_string(layer.rows));
    LayerPattern p(layer.cols, layer.rows, 0);
    p.rgb = std::move(image.pixels);
    CheckTransmittance(p, file);
    t.push_back(std::move(p));
  }
  return t;
}

std::vector<std::string> WriteSolution(const DisplayModel& model, const Patterns& t, const SolverReport& report,
                                       const std::string& folder, const SolutionFiles& what) {
  std::vector<std::string> written;
  std::error_code ec;
  fs::create_directories(fs::path(folder) / "patterns", ec);
  fs::create_directories(fs::path(folder) / "panels", ec);
  if (ec) throw Error(folder + ": cannot create the output folder: " + ec.message());
  SolverReport annotated = report;
  for (size_t k = 0; k < model.layer_count(); ++k) {
    const VirtualLayer& layer = model.system().layers[k];
    WriteExr(PatternFile(folder, layer), Image{t[k].cols, t[k].rows, {"R", "G", "B"}, t[k].rgb});
    written.push_back("patterns/" + layer.name + ".exr");
    PanelEncoding panel = EncodeForPanel(layer, t[k]);
    if (panel.below_black_level)
      annotated.warnings.push_back("panel \"" + layer.name + "\": " + std::to_string(panel.below_black_level) +
                                   " values are darker than its black level and were encoded as 0");
    WritePng8((fs::path(folder) / "panels" / (layer.name + ".png")).string(), panel.cols, panel.rows, 3, panel.pixels);
    written.push_back("panels/" + layer.name + ".png");
  }
  WriteFileAtomically((fs::path(folder) / "trace.csv").string(), TraceCsv(annotated));
  WriteFileAtomically((fs::path(folder) / "report.txt").string(),
                      annotated.FullReport() + "written by " + VersionLine() + "\n");
  WriteFileAtomically((fs::path(folder) / "report.json").string(), ReportToJson(annotated).dump(2) + "\n");
  written.insert(written.end(), {"trace.csv", "report.txt", "report.json"});
  if (what.write_lightfield) {
    // The forward model's: through the LED arrays' spread, the panels' diffraction and response where the
    // solve saw them.
    const std::vector<LayerDiffraction> seen = SeenKernels(model.system(), report.panel_diffraction);
    LightField synthesized = report.lc_response ? ShownLightField(model, t, &seen)
                             : !seen.empty()    ? Synthesize(model, DiffractedPatterns(seen, t))
                                                : Synthesize(model, t);
    synthesized.scene = "synthesized by layerlab " + report.solver + " for " + model.system().file;
    for (const std::string& f : WriteLightField(synthesized, (fs::path(folder) / "lightfield").string()))
      written.push_back("lightfield/" + f);
  }
  return written;
}

}  // namespace layerlab
