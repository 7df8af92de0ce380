#include <algorithm>

#include <ceres/loss_function.h>

#include "layerlab/calibration/fit_steps.h"
#include "layerlab/calibration/intrinsics_propagation.h"

namespace layerlab {

ceres::LossFunction* MakeLoss(RobustLoss loss, double scale) {
  switch (loss) {
    case RobustLoss::kHuber:
      return new ceres::HuberLoss(scale);
    case RobustLoss::kCauchy:
      return new ceres::CauchyLoss(scale);
    case RobustLoss::kNone:
      return nullptr;
  }
  return nullptr;
}

int LayerIndex(const DisplaySystem& system, const std::string& name) {
  for (size_t k = 0; k < system.layers.size(); ++k)
    if (system.layers[k].name == name) return static_cast<int>(k);
  throw Error("no panel named \"" + name + "\"");  // CheckMeasurements has refused it before
}

const CalibratedPanel* CalibratedDisplay::find(const std::string& panel) const {
  for (const CalibratedPanel& p : panels)
    if (p.name == panel) return &p;
  return nullptr;
}

const CalibratedOptic* CalibratedDisplay::find_optic(const std::string& name) const {
  for (const CalibratedOptic& o : optics)
    if (o.name == name) return &o;
  return nullptr;
}

void StartFromScene(const DisplaySystem& system, CalibratedDisplay* display, CalibrationReport* report) {
  *display = CalibratedDisplay{};
  for (const VirtualLayer& layer : system.layers) {
    CalibratedPanel panel;
    panel.name = layer.name;
    panel.behind_optics =
        std::any_of(layer.path.begin(), layer.path.end(), [](const PathStep& s) { return s.power_diopters != 0; });
    panel.distance_m = layer.panel_distance_m;
    panel.gap_m = layer.position_m - (layer.path.empty() ? 0.0 : layer.path.back().position_m.value_or(0.0));
    panel.eye_from_panel_x_m = layer.panel.eye_from_panel_m[0];
    panel.eye_from_panel_y_m = layer.panel.eye_from_panel_m[1];
    panel.rotation_rad = layer.panel.rotation_rad;
    panel.gamma = layer.panel.gamma;
    panel.black_level = layer.panel.black_level;
    display->panels.push_back(panel);
    report->panels.push_back(PanelResiduals{layer.name});
  }
}

namespace {

// With FitChoice::kAuto, a focal length or gap that the fit left undetermined
// (unresolved: a standard deviation above kUndeterminedStdDevFraction of its
// value, or at a bound) is held at its scene value instead, and the fit run
// again: the options for that, and in *held what the report says of each.
CalibrationOptions HoldWhatAutoLeftUnresolved(const CalibrationOptions& options, const CalibrationReport& report,
                                              std::vector<std::string>* held) {
  CalibrationOptions refit = options;
  for (const ParameterEstimate& p : report.parameters) {
    if (p.status != ParameterStatus::kUnresolved) continue;
    FitChoice* choice = p.quantity == "focal_length" ? &refit.focal_length
                        : p.quantity == "gap"        ? &refit.lens_gaps
                                                     : nullptr;
    if (!choice || *choice != FitChoice::kAuto) continue;
    *choice = FitChoice::kHold;
    held->push_back("the " + std::string(p.quantity == "gap" ? "gap" : "focal length") + " of \"" + p.element +
                    "\" was fitted to " + ShowValue(p.quantity, p.value) +
                    (p.std_dev ? " +- " + ShowValue(p.quantity, *p.std_dev) : "") +
                    ", which the data do not determine: it is held at its scene value " +
                    ShowValue(p.quantity, p.scene_value) + " (" +
                    (p.quantity == "gap" ? "--lens-gaps" : "--focal-length") +
                    " auto); add camera positions farther apart to fit it");
  }
  return refit;
}

}  // namespace

CalibrationReport Calibrate(const DisplaySystem& system, const Measurements& measurements,
                            const CalibrationOptions& options, CalibratedDisplay* display) {
  CalibrationReport report;
  report.scene = system.file;
  report.measurements = measurements.file;
  report.options = options;
  std::string invalid;
  if (!options.IsValid(&invalid)) {
    report.message = "invalid options: " + invalid;
    return report;
  }
  try {
    CheckMeasurements(measurements, system);
  } catch (const Error& e) {
    report.message = e.what();
    return report;
  }

  StartFromScene(system, display, &report);
  const CalibratedDisplay designed = *display;
  const CalibrationReport before = report;
  bool geometry = FitGeometry(system, measurements, options, display, &report);
  std::vector<std::string> held;
  const CalibrationOptions refit = HoldWhatAutoLeftUnresolved(options, report, &held);
  if (!held.empty()) {
    *display = designed;
    report = before;
    report.options = refit;
    geometry = FitGeometry(system, measurements, refit, display, &report);
    report.notes.insert(report.notes.begin(), held.begin(), held.end());
  }
  if (!geometry) return report;
  PropagateIntrinsicsUncertainty(system, measurements, &report);
  if (!FitLuminance(system, measurements, options, display, &report)) return report;
  report.usable = true;
  report.message = "fitted " + std::to_string(report.markers) + " markers and " +
                   std::to_string(report.luminance_samples) + " luminance samples";
  return report;
}

}  // namespace layerlab
