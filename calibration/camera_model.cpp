#include "layerlab/calibration/camera_model.h"

#include <cmath>

namespace layerlab {

std::optional<std::array<double, 2>> AngleFromCameraPixel(const CameraIntrinsics& camera, double u, double v) {
  const double xd = (u - camera.cx) / camera.fx, yd = (v - camera.cy) / camera.fy;
  const double rd = std::hypot(xd, yd);
  // Newton on r (1 + k1 r^2 + k2 r^4) = rd, from r = rd; the distortion must
  // stay monotonic on the way or two radii would map to one pixel.
  double r = rd;
  bool converged = rd == 0;
  for (int i = 0; i < 100 && !converged; ++i) {
    const double r2 = r * r;
    const double slope = 1 + 3 * camera.k1 * r2 + 5 * camera.k2 * r2 * r2;
    if (!(slope > 0)) return std::nullopt;
    const double step = (r * (1 + camera.k1 * r2 + camera.k2 * r2 * r2) - rd) / slope;
    r -= step;
    converged = std::abs(step) <= 1e-15 * (1 + r);
  }
  if (!converged || !(r >= 0)) return std::nullopt;
  const double r2 = r * r;
  if (!(1 + 3 * camera.k1 * r2 + 5 * camera.k2 * r2 * r2 > 0)) return std::nullopt;
  const double scale = rd == 0 ? 1.0 : r / rd;
  return std::array<double, 2>{std::atan(xd * scale), std::atan(-yd * scale)};
}

std::array<double, 2> CameraPixelFromAngle(const CameraIntrinsics& camera, double angle_x, double angle_y) {
  const double x = std::tan(angle_x), y = -std::tan(angle_y);
  const double r2 = x * x + y * y;
  const double g = 1 + camera.k1 * r2 + camera.k2 * r2 * r2;
  return {camera.cx + camera.fx * g * x, camera.cy + camera.fy * g * y};
}

}  // namespace layerlab
