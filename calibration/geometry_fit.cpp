#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include <ceres/ceres.h>

#include "framework/params.h"
#include "calibration/fit_steps.h"
#include "calibration/marker_model.h"
#include "calibration/scalar_fit.h"
#include "calibration/similarity_fit.h"

namespace layerlab {
namespace {

struct MarkerDatum {
  int layer = 0;
  size_t capture = 0;
  MarkerPlacement placement;
  Point2 pixel;  // (col, row)
  double angle_x = 0, angle_y = 0;
  Location where;
};

struct MarkerCost {
  MarkerPlacement placement;
  double eye_relief, angle_x, angle_y;

  template <typename T>
  bool operator()(const T* f, const T* s, const T* ox, const T* oy, const T* rotation, const T* pan, const T* tilt,
                  const T* roll, T* residual) const {
    const MarkerParameters<T> q{*f, *s, *ox, *oy, *rotation, *pan, *tilt, *roll};
    T angle[2];
    PredictVisualAngle(q, eye_relief, placement, angle);
    residual[0] = angle[0] - angle_x;
    residual[1] = angle[1] - angle_y;
    return true;
  }
};

using MarkerCostFunction = ceres::AutoDiffCostFunction<MarkerCost, 2, 1, 1, 1, 1, 1, 1, 1, 1>;

// Indices into the ScalarFit of one panel's parameters.
struct PanelIndices {
  int distance = -1, offset_x = -1, offset_y = -1, rotation = -1;
};

std::string Quoted(const std::string& name) { return "\"" + name + "\""; }

double Diopters(double s, double f, double e) { return (f - s) / (s * f + e * (f - s)); }

// Markers that fit a mirror image of the panel far better than the panel as
// the scene mounts it: a "reversed" or a combiner fold that is wrong.
void CheckMirroring(const DisplaySystem& system, const std::vector<std::vector<const MarkerDatum*>>& by_layer,
                    CalibrationReport* report) {
  for (size_t k = 0; k < by_layer.size(); ++k) {
    std::map<size_t, std::pair<std::vector<Point2>, std::vector<Point2>>> by_capture;  // parallax differs per capture
    for (const MarkerDatum* d : by_layer[k]) {
      by_capture[d->capture].first.push_back({d->placement.local_x, d->placement.local_y});
      by_capture[d->capture].second.push_back({std::tan(d->angle_x), std::tan(d->angle_y)});
    }
    double as_given = 0, mirrored = 0;
    size_t count = 0;
    for (auto& [capture, points] : by_capture) {
      auto& [from, to] = points;
      if (Spread(from).collinear) continue;  // a line and its mirror image cannot be told apart
      std::vector<Point2> mirror;
      for (const Point2& p : from) mirror.push_back(std::conj(p));
      const double n = static_cast<double>(from.size());
      as_given += n * std::pow(FitSimilarity(from, to).rms, 2);
      mirrored += n * std::pow(FitSimilarity(mirror, to).rms, 2);
      count += from.size();
    }
    if (count == 0) continue;
    as_given = std::sqrt(as_given / count), mirrored = std::sqrt(mirrored / count);
    if (ArcminFromRadians(as_given) > 1.0 && mirrored < 0.25 * as_given)
      report->warnings.push_back("panel " + Quoted(system.layers[k].name) +
                                 ": its markers fit a mirror image of the panel far better than the panel as the scene "
                                 "mounts it (RMS " + FormatFixed(ArcminFromRadians(mirrored), 3) + " arcmin mirrored, " +
                                 FormatFixed(ArcminFromRadians(as_given), 3) +
                                 " arcmin as mounted): check its \"reversed\" and the combiner's fold");
  }
}

}  // namespace

bool FitGeometry(const DisplaySystem& system, const Measurements& measurements, const CalibrationOptions& options,
                 CalibratedDisplay* display, CalibrationReport* report) {
  const double e = system.eye.eye_relief, f0 = system.focal_length;
  const int layer_count = static_cast<int>(system.layers.size());

  std::vector<MarkerDatum> data;
  std::set<std::pair<double, double>> positions;
  for (size_t c = 0; c < measurements.captures.size(); ++c) {
    const Capture& capture = measurements.captures[c];
    positions.insert({capture.camera_position[0], capture.camera_position[1]});
    for (const PanelMarkers& markers : capture.panels) {
      const int k = LayerIndex(system, markers.panel);
      for (const MarkerObservation& o : markers.markers)
        data.push_back({k, c, PlaceMarker(system.layers[k], o.col, o.row, capture.camera_position[0], capture.camera_position[1]),
                        {o.col, o.row}, o.angle_x, o.angle_y, o.where});
    }
  }
  report->markers = static_cast<int>(data.size());
  report->captures = static_cast<int>(measurements.captures.size());
  report->camera_positions = static_cast<int>(positions.size());
  if (data.empty()) return true;

  std::vector<std::vector<const MarkerDatum*>> by_layer(layer_count);
  for (const MarkerDatum& d : data) by_layer[d.layer].push_back(&d);
  std::vector<PointSpread> spread(layer_count);
  std::vector<int> positions_seen(layer_count, 0);
  for (int k = 0; k < layer_count; ++k) {
    std::vector<Point2> pixels;
    std::set<std::pair<double, double>> seen_from;
    for (const MarkerDatum* d : by_layer[k]) {
      pixels.push_back(d->pixel);
      const auto& position = measurements.captures[d->capture].camera_position;
      seen_from.insert({position[0], position[1]});
    }
    spread[k] = Spread(pixels);
    positions_seen[k] = static_cast<int>(seen_from.size());
  }

  const bool farthest_reference = options.reference == AxisReference::kFarthestPanel;
  if (farthest_reference && spread[0].distinct < 2) {
    report->message = "the axis reference \"farthest-panel\" needs markers at two or more pixels of the farthest panel " +
                      Quoted(system.layers[0].name) + (by_layer[0].empty() ? ", which has none" : "");
    return false;
  }
  CheckMirroring(system, by_layer, report);

  // The parameters, each held where the data's shape cannot determine it.
  ScalarFit fit;
  std::vector<std::string> quantity;
  std::vector<ParameterStatus> status;
  auto add = [&](ScalarParameter p, const std::string& q) {
    quantity.push_back(q);
    status.push_back(ParameterStatus::kFitted);
    return fit.Add(std::move(p));
  };
  auto hold = [&](int index, ParameterStatus why) {
    fit.Hold(index);
    status[index] = why;
  };
  const int focal = add({"the focal length of " + Quoted(system.lens), f0, 0, e * (1 + 1e-6), std::nullopt}, "focal_length");
  const int pan = add({"the camera's pan", 0, 1, {}, {}}, "pan");
  const int tilt = add({"the camera's tilt", 0, 1, {}, {}}, "tilt");
  const int roll = add({"the camera's roll", 0, 1, {}, {}}, "roll");
  std::vector<PanelIndices> index(layer_count);
  for (int k = 0; k < layer_count; ++k) {
    const VirtualLayer& layer = system.layers[k];
    const std::string panel = "panel " + Quoted(layer.name);
    if (by_layer[k].empty()) {
      report->warnings.push_back(panel + " has no markers: its distance, offset and rotation keep their scene values");
      continue;
    }
    const bool reference = farthest_reference && k == 0;
    std::optional<double> beyond_focus;
    if (!options.fit_focal_length) beyond_focus = f0;
    index[k].distance = add({"the distance of " + panel, layer.panel_distance, 2, 1e-3 * f0, beyond_focus}, "distance");
    index[k].rotation = add({"the rotation of " + panel, reference ? 0.0 : layer.panel.rotation, 3, {}, {}}, "rotation");
    index[k].offset_x = add({"the offset x of " + panel, reference ? 0.0 : layer.panel.offset[0], 4, {}, {}}, "offset_x");
    index[k].offset_y = add({"the offset y of " + panel, reference ? 0.0 : layer.panel.offset[1], 4, {}, {}}, "offset_y");
    if (reference)
      for (int i : {index[k].rotation, index[k].offset_x, index[k].offset_y}) hold(i, ParameterStatus::kReference);
    if (spread[k].distinct == 1) {
      // One pixel fixes where the panel is, not how it is turned; its size
      // only through parallax, when it is seen from two camera positions.
      const bool parallax = positions_seen[k] >= 2;
      if (!parallax) hold(index[k].distance, ParameterStatus::kUndetermined);
      if (!reference) hold(index[k].rotation, ParameterStatus::kUndetermined);
      const Point2 pixel = by_layer[k].front()->pixel;
      report->warnings.push_back(
          panel + ": its markers show a single panel pixel (" + FormatFixed(pixel.real(), 1) + ", " +
          FormatFixed(pixel.imag(), 1) + "), which fixes the offset but not the rotation" +
          (parallax ? "" : " nor the magnification") + ": its " + (parallax ? "rotation keeps its scene value (" :
          "distance and rotation keep their scene values (" + ShowValue("distance", layer.panel_distance) + ", ") +
          ShowValue("rotation", layer.panel.rotation) + "); show markers at three or more pixels not on one line");
    } else if (spread[k].collinear) {
      report->warnings.push_back(panel + ": its markers lie on one line of the panel, so its magnification and rotation "
                                         "rest on that line's length and tilt alone and nothing checks the other "
                                         "direction; add markers off the line");
    }
  }
  if (!options.fit_focal_length) {
    hold(focal, ParameterStatus::kNotFitted);
  } else {
    bool parallax = false;
    for (int k = 0; k < layer_count; ++k)
      parallax = parallax || (index[k].distance >= 0 && !fit.held(index[k].distance) && positions_seen[k] >= 2);
    if (!parallax) {
      hold(focal, ParameterStatus::kUndetermined);
      report->warnings.push_back("the focal length cannot be told from the panel distances while each panel is seen "
                                 "from one camera position only: it keeps its scene value (" +
                                 ShowValue("focal_length", f0) + "); add captures from other camera positions "
                                 "(\"camera_position\") to fit it");
    }
  }
  if (!farthest_reference)
    for (int i : {pan, tilt, roll}) hold(i, ParameterStatus::kReference);

  for (const MarkerDatum& d : data) {
    const PanelIndices& p = index[d.layer];
    fit.AddResidual(new MarkerCostFunction(new MarkerCost{d.placement, e, d.angle_x, d.angle_y}),
                    MakeLoss(options.loss, options.marker_loss_scale),
                    {focal, p.distance, p.offset_x, p.offset_y, p.rotation, pan, tilt, roll});
  }

  ScalarFitOptions fit_options;
  fit_options.max_iterations = options.max_iterations;
  fit_options.function_tolerance = options.function_tolerance;
  fit_options.parameter_tolerance = options.parameter_tolerance;
  fit_options.robust_noise = options.loss != RobustLoss::kNone;
  ScalarFitResult result = fit.Solve(fit_options);
  report->geometry_solver = result.summary.BriefReport();
  if (!result.usable) {
    report->message = "the geometry fit failed: " + result.summary.message;
    return false;
  }
  for (const UndeterminedParameter& u : result.undetermined) {
    status[u.index] = ParameterStatus::kUndetermined;
    std::vector<std::string> partners;
    for (int i : u.partners) partners.push_back(fit.parameter(i).name);
    report->warnings.push_back("the data do not determine " + fit.parameter(u.index).name + " (it trades off against " +
                               JoinWords(partners, " and ") + " without changing any residual): it keeps its scene "
                               "value (" + ShowValue(quantity[u.index], fit.parameter(u.index).start) + ")");
  }
  const double f = fit.value(focal);
  for (int k = 0; k < layer_count; ++k)
    if (index[k].distance >= 0 && fit.value(index[k].distance) > f) {
      report->message = "the fit puts panel " + Quoted(system.layers[k].name) + " " +
                        ShowValue("distance", fit.value(index[k].distance)) + " from the lens, beyond the focal length " +
                        ShowValue("focal_length", f) + ": the measurements do not match this display";
      return false;
    }
  report->marker_noise = result.noise;
  if (result.covariance.size() == 0)
    report->warnings.push_back("no uncertainties for the geometry: " + result.covariance_message);

  // Residuals before (the scene as designed, seen by an unturned camera) and after.
  auto parameters_before = [&](int k) {
    const VirtualLayer& layer = system.layers[k];
    return MarkerParameters<double>{f0, layer.panel_distance, layer.panel.offset[0], layer.panel.offset[1],
                                    layer.panel.rotation, 0, 0, 0};
  };
  auto parameters_after = [&](int k) {
    const PanelIndices& p = index[k];
    return MarkerParameters<double>{f, fit.value(p.distance), fit.value(p.offset_x), fit.value(p.offset_y),
                                    fit.value(p.rotation), fit.value(pan), fit.value(tilt), fit.value(roll)};
  };
  std::vector<double> before(layer_count, 0.0), after(layer_count, 0.0), components;
  double sum_before = 0, sum_after = 0;
  std::vector<std::pair<double, const MarkerDatum*>> errors;
  for (const MarkerDatum& d : data) {
    double a[2], b[2];
    PredictVisualAngle(parameters_before(d.layer), e, d.placement, a);
    PredictVisualAngle(parameters_after(d.layer), e, d.placement, b);
    const double error_before = std::pow(a[0] - d.angle_x, 2) + std::pow(a[1] - d.angle_y, 2);
    const double error_after = std::pow(b[0] - d.angle_x, 2) + std::pow(b[1] - d.angle_y, 2);
    before[d.layer] += error_before, after[d.layer] += error_after;
    sum_before += error_before, sum_after += error_after;
    components.push_back(std::abs(b[0] - d.angle_x));
    components.push_back(std::abs(b[1] - d.angle_y));
    errors.push_back({std::sqrt(error_after), &d});
  }
  report->marker_rms_before = std::sqrt(sum_before / data.size());
  report->marker_rms_after = std::sqrt(sum_after / data.size());
  for (int k = 0; k < layer_count; ++k) {
    if (by_layer[k].empty()) continue;
    PanelResiduals& r = report->panels[k];
    r.markers = static_cast<int>(by_layer[k].size());
    r.marker_rms_before = std::sqrt(before[k] / r.markers);
    r.marker_rms_after = std::sqrt(after[k] / r.markers);
  }
  if (options.loss == RobustLoss::kNone && components.size() > 8) {
    // Gross errors stand out against the median's noise, which they do not inflate.
    std::nth_element(components.begin(), components.begin() + components.size() / 2, components.end());
    const double sigma = 1.4826 * components[components.size() / 2];
    auto worst = std::max_element(errors.begin(), errors.end());
    const long beyond = std::count_if(errors.begin(), errors.end(), [&](const auto& x) { return x.first > 6 * sigma; });
    if (sigma > 0 && beyond > 0)
      report->warnings.push_back(std::to_string(beyond) + " marker" + (beyond > 1 ? "s lie" : " lies") +
                                 " beyond 6 sigma of the noise (the worst " +
                                 FormatFixed(ArcminFromRadians(worst->first), 3) + " arcmin, at " +
                                 worst->second->where.str() + "): outliers bias a least-squares fit; a robust loss "
                                 "(huber or cauchy) discounts them");
  }

  // The results, by parameter.
  auto estimate = [&](const std::string& element, int i) {
    ParameterEstimate p;
    p.element = element;
    p.quantity = quantity[i];
    p.scene_value = fit.parameter(i).start;
    p.value = fit.value(i);
    p.status = status[i];
    if (p.status == ParameterStatus::kFitted && result.covariance.size()) p.std_dev = std::sqrt(result.covariance(i, i));
    return p;
  };
  ParameterEstimate lens = estimate(system.lens, focal);
  report->parameters.push_back(lens);
  display->focal_length = f;
  display->focal_length_fitted = lens.status == ParameterStatus::kFitted;
  for (int k = 0; k < layer_count; ++k) {
    if (by_layer[k].empty()) continue;
    const VirtualLayer& layer = system.layers[k];
    const PanelIndices& p = index[k];
    ParameterEstimate distance = estimate(layer.name, p.distance);
    ParameterEstimate depth = distance;
    depth.quantity = "virtual_depth";
    depth.derived = true;
    depth.scene_value = layer.diopters;
    const double s = distance.value;
    depth.value = Diopters(s, f, e);
    if (distance.std_dev) {
      // Propagated through D(s, f) with the covariance of (s, f).
      const double q = s * f + e * (f - s), n = f - s;
      const double ds = (-q - n * (f - e)) / (q * q), df = (q - n * (s + e)) / (q * q);
      const Eigen::MatrixXd& c = result.covariance;
      const double variance = ds * ds * c(p.distance, p.distance) + 2 * ds * df * c(p.distance, focal) +
                              df * df * c(focal, focal);
      depth.std_dev = std::sqrt(std::max(0.0, variance));
    }
    report->parameters.push_back(distance);
    report->parameters.push_back(depth);
    for (int i : {p.offset_x, p.offset_y, p.rotation}) report->parameters.push_back(estimate(layer.name, i));

    CalibratedPanel& out = display->panels[k];
    out.geometry_measured = true;
    out.distance = s;
    out.offset_x = fit.value(p.offset_x);
    out.offset_y = fit.value(p.offset_y);
    out.rotation = fit.value(p.rotation);
  }
  if (farthest_reference)
    for (int i : {pan, tilt, roll}) report->parameters.push_back(estimate("camera", i));
  return true;
}

}  // namespace layerlab
