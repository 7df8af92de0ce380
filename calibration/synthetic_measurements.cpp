#include "layerlab/calibration/synthetic_measurements.h"

#include <cmath>
#include <numbers>

#include <Eigen/Geometry>

#include "layerlab/framework/random.h"
#include "layerlab/systems/layer_ray_map.h"

namespace layerlab {
namespace {

std::vector<double> Spaced(int count, double first, double last) {
  std::vector<double> out;
  for (int i = 0; i < count; ++i)
    out.push_back(std::round(count == 1 ? 0.5 * (first + last) : first + (last - first) * i / (count - 1)));
  return out;
}

}  // namespace

std::array<double, 2> PanelPoint(const VirtualLayer& layer, double col, double row) {
  const PanelSpec& p = layer.panel;
  // The pixel in eye-space order: a flipped axis counts from the other end (display_system.h).
  double j = col - static_cast<double>(p.active_left), i = row - static_cast<double>(p.active_top);
  if (layer.flip_x) j = static_cast<double>(p.active_cols) - 1 - j;
  if (layer.flip_y) i = static_cast<double>(p.active_rows) - 1 - i;
  const Eigen::Vector2d local((j + 0.5 - 0.5 * static_cast<double>(p.active_cols)) * p.pitch_x_m,
                              (0.5 * static_cast<double>(p.active_rows) - i - 0.5) * p.pitch_y_m);
  const Eigen::Vector2d on_panel =
      Eigen::Vector2d(p.eye_from_panel_m[0], p.eye_from_panel_m[1]) + Eigen::Rotation2Dd(p.rotation_rad) * local;
  return {on_panel.x(), on_panel.y()};
}

std::array<double, 2> PanelPixelAt(const VirtualLayer& layer, const std::array<double, 2>& point) {
  const PanelSpec& p = layer.panel;
  const Eigen::Vector2d local =
      Eigen::Rotation2Dd(-p.rotation_rad) *
      (Eigen::Vector2d(point[0], point[1]) - Eigen::Vector2d(p.eye_from_panel_m[0], p.eye_from_panel_m[1]));
  double j = local.x() / p.pitch_x_m - 0.5 + 0.5 * static_cast<double>(p.active_cols);
  double i = 0.5 * static_cast<double>(p.active_rows) - 0.5 - local.y() / p.pitch_y_m;
  if (layer.flip_x) j = static_cast<double>(p.active_cols) - 1 - j;
  if (layer.flip_y) i = static_cast<double>(p.active_rows) - 1 - i;
  return {j + static_cast<double>(p.active_left), i + static_cast<double>(p.active_top)};
}

// The ray leaving pupil point c with slope u meets the unfolded panel plane at A c + B u
// (ray_transfer.h), where the panel point lies turned by 180 degrees when the image is
// inverted (B < 0; the flips of PanelPoint include that turn).
std::array<double, 2> PanelPointOfRay(const VirtualLayer& layer, const std::array<double, 2>& position,
                                      const std::array<double, 2>& slope) {
  const RayTransfer<double>& m = layer.transfer;
  const double sign = m.b < 0 ? -1.0 : 1.0;
  return {sign * (m.a * position[0] + m.b * slope[0]), sign * (m.a * position[1] + m.b * slope[1])};
}

std::array<double, 2> RaySlopeTo(const VirtualLayer& layer, const std::array<double, 2>& point,
                                 const std::array<double, 2>& position) {
  const RayTransfer<double>& m = layer.transfer;
  const double sign = m.b < 0 ? -1.0 : 1.0;
  return {(sign * point[0] - m.a * position[0]) / m.b, (sign * point[1] - m.a * position[1]) / m.b};
}

namespace {

// Behind real lenses: the slope whose exact trace (green, a gray camera's)
// meets `point`, by Newton's method from the first-order slope; NaN where
// the lenses lose the rays near it.
std::array<double, 2> TracedSlopeTo(const VirtualLayer& layer, const std::array<double, 2>& point,
                                    const std::array<double, 2>& position) {
  const LayerRayMap& map = layer.ray_map->exact();
  const double b = std::abs(layer.transfer.b);
  auto point_of = [&](const Eigen::Vector2d& u) -> std::optional<Eigen::Vector2d> {
    const auto traced = map.Trace(1, position[0], position[1], u.x(), u.y());
    if (!traced) return std::nullopt;
    return Eigen::Vector2d(b * (*traced)[0], b * (*traced)[1]);
  };
  const std::array<double, 2> start = RaySlopeTo(layer, point, position);
  Eigen::Vector2d u(start[0], start[1]);
  const Eigen::Vector2d wanted(point[0], point[1]);
  for (int iteration = 0; iteration < 30; ++iteration) {
    const auto at = point_of(u);
    if (!at) break;
    const Eigen::Vector2d miss = *at - wanted;
    if (miss.norm() < 1e-13) return {u.x(), u.y()};
    const double h = 1e-7;
    const auto dx = point_of(u + Eigen::Vector2d(h, 0)), dy = point_of(u + Eigen::Vector2d(0, h));
    if (!dx || !dy) break;
    Eigen::Matrix2d jacobian;
    jacobian.col(0) = (*dx - *at) / h, jacobian.col(1) = (*dy - *at) / h;
    u -= jacobian.inverse() * miss;
  }
  return {NAN, NAN};
}

}  // namespace

std::array<double, 2> ImagedMarker(const DisplaySystem& truth, const VirtualLayer& layer, double col, double row,
                                   const SyntheticCamera& camera, const std::array<double, 2>& position) {
  const std::array<double, 2> slope = layer.ray_map ? TracedSlopeTo(layer, PanelPoint(layer, col, row), position)
                                                    : RaySlopeTo(layer, PanelPoint(layer, col, row), position);
  const Eigen::Vector3d ray(slope[0], slope[1], 1.0);
  const Eigen::Vector3d turn(-camera.tilt_rad, camera.pan_rad, camera.roll_rad);
  const Eigen::Matrix3d eye_from_camera = turn.norm() > 0
                                              ? Eigen::AngleAxisd(turn.norm(), turn.normalized()).toRotationMatrix()
                                              : Eigen::Matrix3d::Identity();
  const Eigen::Vector3d seen = eye_from_camera.transpose() * ray;
  return {std::atan(seen.x() / seen.z()), std::atan(seen.y() / seen.z())};
}

std::vector<Capture> SyntheticCaptures(const DisplaySystem& truth, const MarkerGrid& grid,
                                       const SyntheticCamera& camera, const SyntheticNoise& noise) {
  RefuseTiltedPanels(truth, "synthetic measurements");
  Gaussian gaussian(noise.seed);
  std::vector<Capture> captures;
  for (size_t c = 0; c < camera.positions_m.size(); ++c) {
    Capture capture;
    capture.camera_position = camera.positions_m[c];
    capture.where = {"synthetic", "/captures/" + std::to_string(c)};
    for (const VirtualLayer& layer : truth.layers) {
      const PanelSpec& p = layer.panel;
      PanelMarkers markers;
      markers.panel = layer.name;
      markers.where = capture.where.child("markers").child(layer.name);
      const double cols = static_cast<double>(p.active_cols) - 1, rows = static_cast<double>(p.active_rows) - 1;
      for (double row : Spaced(grid.rows, p.active_top + grid.inset * rows, p.active_top + (1 - grid.inset) * rows))
        for (double col :
             Spaced(grid.cols, p.active_left + grid.inset * cols, p.active_left + (1 - grid.inset) * cols)) {
          MarkerObservation m;
          m.col = col;
          m.row = row;
          m.where = markers.where.child(markers.markers.size());
          auto angle = ImagedMarker(truth, layer, col, row, camera, capture.camera_position);
          if (std::isnan(angle[0])) continue;  // lost in real lenses
          angle[0] += noise.marker_sigma_rad * gaussian();
          angle[1] += noise.marker_sigma_rad * gaussian();
          if (noise.outlier_fraction > 0 && gaussian.uniform() < noise.outlier_fraction) {
            const double direction = 2 * std::numbers::pi * gaussian.uniform();
            angle[0] += noise.outlier_size_rad * std::cos(direction);
            angle[1] += noise.outlier_size_rad * std::sin(direction);
          }
          m.angle_x = angle[0];
          m.angle_y = angle[1];
          if (camera.intrinsics) m.camera_pixel = CameraPixelFromAngle(*camera.intrinsics, angle[0], angle[1]);
          markers.markers.push_back(m);
        }
      capture.panels.push_back(std::move(markers));
    }
    captures.push_back(std::move(capture));
  }
  return captures;
}

PanelLuminance SyntheticLuminance(const std::string& panel, const std::vector<int>& codes, double max_luminance,
                                  double black_level, double gamma, const SyntheticNoise& noise) {
  Gaussian gaussian(noise.seed);
  PanelLuminance curve;
  curve.panel = panel;
  curve.levels = InputLevels::k8Bit;
  curve.where = {"synthetic", "/luminance/" + panel};
  for (int code : codes) {
    const double x = code / 255.0;
    const double ideal = max_luminance * (black_level + (1 - black_level) * std::pow(x, gamma));
    const double reading = std::max(0.0, ideal + noise.luminance_sigma * max_luminance * gaussian());
    curve.samples.push_back({x, reading, curve.where.child("samples").child(curve.samples.size())});
  }
  return curve;
}

}  // namespace layerlab
