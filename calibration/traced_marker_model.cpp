#include "layerlab/calibration/traced_marker_model.h"

#include <cmath>

#include <Eigen/LU>

#include "layerlab/framework/error.h"

namespace layerlab {
namespace {

constexpr int kGreen = 1;
constexpr double kAngleStep = 1e-6;  // rad, for J0 by central differences

}  // namespace

TracedLayerModel::TracedLayerModel(const VirtualLayer& layer, const MarkerParameters<double>& designed)
    : map_(layer.ray_map ? &layer.ray_map->exact() : nullptr),
      sign_b_(layer.transfer.b < 0 ? -1.0 : 1.0),
      designed_(designed) {
  if (!map_) throw Error("internal error: the traced marker model for layer \"" + layer.name + "\" without a ray map");
  if (map_->panel_tilted()) throw Error("internal error: the traced marker model for a tilted panel");
  // The ray map's elements: the path's placed lenses and mirrors with power or surfaces; the fit's: those with power.
  int fitted = 0;
  for (const PathStep& step : layer.path) {
    if (!step.position_m || step.kind == ElementKind::kPanel) continue;
    if (!step.lens_system && step.power_diopters == 0) continue;
    fit_element_.push_back(step.power_diopters != 0 ? fitted++ : -1);
  }
  if (static_cast<int>(fit_element_.size()) != map_->element_count() ||
      static_cast<size_t>(fitted) != designed.gaps.size())
    throw Error("internal error: layer \"" + layer.name + "\": " + std::to_string(map_->element_count()) +
                " elements in its ray map, " + std::to_string(fitted) + " with power, " +
                std::to_string(designed.gaps.size()) + " in the fit");
}

std::optional<std::array<double, 2>> TracedLayerModel::Seen(const MarkerParameters<double>& q, double camera_x_m,
                                                            double camera_y_m, double angle_x, double angle_y) const {
  const double camera[3] = {std::tan(angle_x), std::tan(angle_y), 1.0};
  const double eye_from_camera[3] = {-q.tilt, q.pan, q.roll};  // R_cam
  double e[3];
  ceres::AngleAxisRotatePoint(eye_from_camera, camera, e);
  if (!(e[2] > 0)) return std::nullopt;

  RayMapAdjustment a;
  double moved = 0;
  for (size_t i = 0; i < fit_element_.size(); ++i) {
    const int j = fit_element_[i];
    if (j >= 0) moved += q.gaps[j] - designed_.gaps[j];
    a.element_moved_m.push_back(moved);
    const bool ideal = j >= 0 && !map_->element_is_real_lens(static_cast<int>(i));
    a.element_power_diopters.push_back(ideal ? 1.0 / q.focal_lengths[j] : NAN);
  }
  a.panel_moved_m = moved + (q.distance - designed_.distance);
  const auto x = map_->PanelPoint(kGreen, camera_x_m, camera_y_m, e[0] / e[2], e[1] / e[2], a);
  if (!x) return std::nullopt;
  return std::array<double, 2>{sign_b_ * (*x)[0], sign_b_ * (*x)[1]};
}

std::optional<TracedMarker> TracedLayerModel::Prepare(const MarkerPlacement& m, double angle_x, double angle_y) const {
  TracedMarker t{m, angle_x, angle_y, Eigen::Matrix2d::Identity()};
  Eigen::Matrix2d jacobian;
  for (int axis = 0; axis < 2; ++axis) {
    const double h = kAngleStep;
    const auto plus =
        Seen(designed_, m.camera_x_m, m.camera_y_m, angle_x + (axis == 0 ? h : 0), angle_y + (axis == 1 ? h : 0));
    const auto minus =
        Seen(designed_, m.camera_x_m, m.camera_y_m, angle_x - (axis == 0 ? h : 0), angle_y - (axis == 1 ? h : 0));
    if (!plus || !minus) return std::nullopt;
    jacobian(0, axis) = ((*plus)[0] - (*minus)[0]) / (2 * h);
    jacobian(1, axis) = ((*plus)[1] - (*minus)[1]) / (2 * h);
  }
  if (!(std::abs(jacobian.determinant()) > 0)) return std::nullopt;
  t.inverse_jacobian = jacobian.inverse();
  return t;
}

double TracedLayerModel::Diopters(const MarkerParameters<double>& q) const {
  const double h = 1e-6;  // m of pupil, and rad: paraxial
  MarkerParameters<double> straight = q;
  straight.pan = straight.tilt = straight.roll = 0;
  auto x_of = [&](double p, double u) {
    const auto x = Seen(straight, p, 0, std::atan(u), 0);
    if (!x) throw Error("internal error: a paraxial ray is lost on a traced layer");
    return (*x)[0];
  };
  const double dx_dp = (x_of(h, 0) - x_of(-h, 0)) / (2 * h), dx_du = (x_of(0, h) - x_of(0, -h)) / (2 * h);
  return dx_dp / dx_du;
}

bool TracedLayerModel::AngleError(const MarkerParameters<double>& q, const TracedMarker& m, double error[2]) const {
  const auto seen = Seen(q, m.placement.camera_x_m, m.placement.camera_y_m, m.angle_x, m.angle_y);
  if (!seen) return false;
  const double c = std::cos(q.rotation), s = std::sin(q.rotation);
  const double x = q.eye_from_panel_x_m + c * m.placement.local_x_m - s * m.placement.local_y_m;
  const double y = q.eye_from_panel_y_m + s * m.placement.local_x_m + c * m.placement.local_y_m;
  const Eigen::Vector2d r = -(m.inverse_jacobian * Eigen::Vector2d((*seen)[0] - x, (*seen)[1] - y));
  error[0] = r[0], error[1] = r[1];
  return true;
}

}  // namespace layerlab
