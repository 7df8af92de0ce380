#include "layerlab/calibration/intrinsics_propagation.h"

#include <cmath>
#include <map>

#include "layerlab/calibration/fit_steps.h"

namespace layerlab {
namespace {

// The measurements with every marker's angle read through `camera`; false when some pixel cannot be.
bool ReadThrough(const CameraIntrinsics& camera, Measurements* m) {
  m->camera = camera;
  for (Capture& c : m->captures)
    for (PanelMarkers& p : c.panels)
      for (MarkerObservation& o : p.markers) {
        if (!o.camera_pixel) continue;
        const auto angle = AngleFromCameraPixel(camera, (*o.camera_pixel)[0], (*o.camera_pixel)[1]);
        if (!angle) return false;
        o.angle_x = (*angle)[0], o.angle_y = (*angle)[1];
      }
  return true;
}

bool HasCameraPixels(const Measurements& m) {
  for (const Capture& c : m.captures)
    for (const PanelMarkers& p : c.panels)
      for (const MarkerObservation& o : p.markers)
        if (o.camera_pixel) return true;
  return false;
}

// The geometry as fitted to `m` (the report's parameters by element and quantity); empty when the fit fails.
std::map<std::pair<std::string, std::string>, double> Refit(const DisplaySystem& system, const Measurements& m,
                                                            const CalibrationOptions& options) {
  CalibrationReport report;
  CalibratedDisplay display;
  StartFromScene(system, &display, &report);
  CalibrationOptions refit = options;
  refit.accept_model_error = true;  // the change of the values is what counts here
  std::map<std::pair<std::string, std::string>, double> values;
  if (!FitGeometry(system, m, refit, &display, &report)) return values;
  for (const ParameterEstimate& p : report.parameters) values[{p.element, p.quantity}] = p.value;
  return values;
}

}  // namespace

void PropagateIntrinsicsUncertainty(const DisplaySystem& system, const Measurements& measurements,
                                    CalibrationReport* report) {
  if (!measurements.camera || !measurements.camera->uncertainty || !HasCameraPixels(measurements)) return;
  const CameraIntrinsics& camera = *measurements.camera;
  const CameraIntrinsicsUncertainty& sd = *camera.uncertainty;
  std::map<std::pair<std::string, std::string>, double> added;  // variance, SI^2
  int moved = 0;
  for (const auto& [field, sigma] :
       std::vector<std::pair<double CameraIntrinsics::*, double>>{{&CameraIntrinsics::fx, sd.fx_px},
                                                                  {&CameraIntrinsics::fy, sd.fy_px},
                                                                  {&CameraIntrinsics::cx, sd.cx_px},
                                                                  {&CameraIntrinsics::cy, sd.cy_px},
                                                                  {&CameraIntrinsics::k1, sd.k1},
                                                                  {&CameraIntrinsics::k2, sd.k2}}) {
    if (!(sigma > 0)) continue;
    CameraIntrinsics perturbed = camera;
    perturbed.*field += sigma;
    Measurements m = measurements;
    if (!ReadThrough(perturbed, &m)) continue;
    const auto values = Refit(system, m, report->options);
    if (values.empty()) continue;
    ++moved;
    for (const ParameterEstimate& p : report->parameters)
      if (auto it = values.find({p.element, p.quantity}); it != values.end() && p.std_dev)
        added[{p.element, p.quantity}] += std::pow(it->second - p.value, 2);
  }
  if (moved == 0) return;
  const ParameterEstimate* grew_most = nullptr;
  double most = 0, before = 0;
  for (ParameterEstimate& p : report->parameters) {
    if (!p.std_dev || !added.count({p.element, p.quantity})) continue;
    const double was = *p.std_dev;
    p.std_dev = std::sqrt(was * was + added[{p.element, p.quantity}]);
    if (was > 0 && *p.std_dev / was > most) most = *p.std_dev / was, grew_most = &p, before = was;
  }
  if (grew_most)
    report->notes.push_back(
        "the camera's intrinsics' uncertainty (" + std::to_string(moved) +
        " of them refitted one standard deviation off) is included in the standard deviations; it widens most that "
        "of " +
        grew_most->element + " " + grew_most->quantity + ", from " + ShowValue(grew_most->quantity, before) + " to " +
        ShowValue(grew_most->quantity, *grew_most->std_dev));
}

}  // namespace layerlab
