// The measuring camera: pinhole intrinsics with Brown radial distortion.
//
// Camera pixels count u to the right and v downward, integers at pixel
// centers (as OpenCV does). The normalized, distorted coordinates are
//   x_d = (u - cx) / fx,   y_d = (v - cy) / fy,
// and the undistorted ones (x, y) satisfy (x_d, y_d) = (x, y) (1 + k1 r^2 + k2 r^4),
// r^2 = x^2 + y^2. The camera looks along +z with its rows level, so a marker
// at (x, y) lies in the direction (x, -y, 1) of eye space (x right, y up), at
// visual angles (atan x, atan -y).
#pragma once

#include <array>
#include <optional>

namespace layerlab {

// One standard deviation of each intrinsic, as estimated from photographs of a chessboard
// (`layerlab camera-intrinsics`), with the root-mean-square reprojection error of that estimate.
struct CameraIntrinsicsUncertainty {
  double fx_px = 0, fy_px = 0, cx_px = 0, cy_px = 0;
  double k1 = 0, k2 = 0;
  double rms_reprojection_px = 0;
};

struct CameraIntrinsics {
  double fx = 0, fy = 0;                                   // focal length in pixels
  double cx = 0, cy = 0;                                   // principal point, pixels
  double k1 = 0, k2 = 0;                                   // radial distortion
  std::optional<CameraIntrinsicsUncertainty> uncertainty;  // when estimated by layerlab
};

// Visual angles (rad, x right, y up) of a camera pixel; empty where the
// distortion cannot be inverted (beyond the radius where it folds back).
std::optional<std::array<double, 2>> AngleFromCameraPixel(const CameraIntrinsics& camera, double u, double v);

// The camera pixel showing the direction at visual angles (ax, ay), |a| < 90 deg.
std::array<double, 2> CameraPixelFromAngle(const CameraIntrinsics& camera, double angle_x, double angle_y);

}  // namespace layerlab
