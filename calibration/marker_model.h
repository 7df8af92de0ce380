// Where a panel pixel appears to a camera at the eye: the geometric model the
// calibration fits (templated for Ceres' automatic derivatives).
//
// A marker at panel pixel (col c, row r) of the full grid, on a panel with
// active region (left, top, cols x rows) and pitches (p_x, p_y), lies at
//   l = (sx (c - left + 1/2 - cols/2) p_x,  sy (rows/2 - (r - top) - 1/2) p_y)
// from the active region's center, in eye-space order (x right, y up): sx, sy
// are -1 on an axis the compiled layer flips (a reversed panel, a mirrored
// branch), which is display_system.h's pixel convention with the mirroring
// undone. Placed at offset o and rotation theta in its plane, at distance s
// behind a thin lens of focal length f with the pupil e in front of it, the
// pupil center sees it at tan-angle (optics.h, Eq. 1)
//   t0 = T (o + R(theta) l),   T = f / (s f + e (f - s))   [tan per meter],
// and a camera displaced by c in the pupil plane sees the image plane
// (D = (f - s) / (s f + e (f - s)) diopters) with parallax:
//   t = t0 - c D.
// The camera may be turned against the eye's axes (pan right, tilt up, roll
// counterclockwise as the eye sees it): R_cam is the rotation by the vector
// (-tilt, pan, roll), and the camera sees d = R_cam^T (t, 1) at the visual
// angles (atan(d_x / d_z), atan(d_y / d_z)). Everything stays finite at the
// focal plane (D = 0).
#pragma once

#include <cmath>

#include <ceres/rotation.h>

#include "systems/display_system.h"

namespace layerlab {

// What the model needs to know of one marker besides the fitted parameters.
struct MarkerPlacement {
  double local_x = 0, local_y = 0;    // l, m
  double camera_x = 0, camera_y = 0;  // c, m
};

inline MarkerPlacement PlaceMarker(const VirtualLayer& layer, double col, double row, double camera_x, double camera_y) {
  const PanelSpec& p = layer.panel;
  const double x = (col - static_cast<double>(p.active_left) + 0.5 - 0.5 * static_cast<double>(p.active_cols)) * p.pitch_x;
  const double y = (0.5 * static_cast<double>(p.active_rows) - (row - static_cast<double>(p.active_top)) - 0.5) * p.pitch_y;
  return {layer.flip_x ? -x : x, layer.flip_y ? -y : y, camera_x, camera_y};
}

// The fitted parameters of the model, by role.
template <typename T>
struct MarkerParameters {
  T focal_length, distance, offset_x, offset_y, rotation;
  T pan, tilt, roll;
};

template <typename T>
void PredictVisualAngle(const MarkerParameters<T>& q, double eye_relief, const MarkerPlacement& m, T angle[2]) {
  using std::atan;
  using std::cos;
  using std::sin;
  const T denominator = q.distance * q.focal_length + eye_relief * (q.focal_length - q.distance);
  const T tan_per_meter = q.focal_length / denominator;
  const T diopters = (q.focal_length - q.distance) / denominator;
  const T c = cos(q.rotation), s = sin(q.rotation);
  const T x = q.offset_x + c * m.local_x - s * m.local_y;
  const T y = q.offset_y + s * m.local_x + c * m.local_y;
  const T eye_direction[3] = {tan_per_meter * x - m.camera_x * diopters, tan_per_meter * y - m.camera_y * diopters, T(1)};
  const T camera_from_eye[3] = {q.tilt, -q.pan, -q.roll};  // the inverse of R_cam
  T d[3];
  ceres::AngleAxisRotatePoint(camera_from_eye, eye_direction, d);
  angle[0] = atan(d[0] / d[2]);
  angle[1] = atan(d[1] / d[2]);
}

}  // namespace layerlab
