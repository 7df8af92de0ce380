#include <algorithm>

#include <ceres/loss_function.h>

#include "layerlab/calibration/fit_steps.h"

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
    report.panels.push_back(PanelResiduals{layer.name});
  }
  if (!FitGeometry(system, measurements, options, display, &report)) return report;
  if (!FitLuminance(system, measurements, options, display, &report)) return report;
  report.usable = true;
  report.message = "fitted " + std::to_string(report.markers) + " markers and " +
                   std::to_string(report.luminance_samples) + " luminance samples";
  return report;
}

}  // namespace layerlab
