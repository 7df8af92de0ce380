// Where a panel pixel appears to a camera at the eye: the geometric model the
// calibration fits (templated for Ceres' automatic derivatives).
//
// A marker at panel pixel (col c, row r) of the full grid, on a panel with
// active region (left, top, cols x rows) and pitches (p_x, p_y), lies at
//   l = (sx (c - left + 1/2 - cols/2) p_x,  sy (rows/2 - (r - top) - 1/2) p_y)
// from the active region's center, in eye-space order (x right, y up): sx, sy
// are -1 on an axis the compiled layer flips (a reversed panel, a mirrored
// branch, an inverted image), which is display_system.h's pixel convention
// with the mirroring undone. Placed at offset o and rotation theta in its
// plane, it is seen through the layer's path: the elements with power on it
// (lenses, curved mirrors) at the path lengths their gaps set, each of focal
// length f_i, and the panel at its distance s behind the last of them (from
// the pupil without one) compose the ray transfer (systems/ray_transfer.h)
//   M = T(s) L(1/f_n) T(c_n + g_n) ... L(1/f_1) T(c_1 + g_1),
// where g_i is element i's gap and c_i the path length between it and the
// element with power before it that no fitted gap covers (flat elements:
// half mirrors, fold mirrors, combiners). The pupil center sees the panel point
// at tan-angle t0 = (o + R(theta) l) / |B|, moved radially by the elements'
// distortion k_i (a real magnifier's, which the paraxial M lacks; 0 for an
// ideal lens): t0 (1 + sum k_i |t0|^2); and a camera displaced by c in the
// pupil plane sees the image plane (A / B diopters) with parallax:
//   t = t0 (1 + sum k_i |t0|^2) - c A / B.
// The camera may be turned against the eye's axes (pan right, tilt up, roll
// counterclockwise as the eye sees it): R_cam is the rotation by the vector
// (-tilt, pan, roll), and the camera sees d = R_cam^T (t, 1) at the visual
// angles (atan(d_x / d_z), atan(d_y / d_z)). Everything stays finite at the
// focal plane (A = 0).
#pragma once

#include <cmath>
#include <vector>

#include <ceres/rotation.h>

#include "layerlab/systems/display_system.h"

namespace layerlab {

// What the model needs to know of one marker besides the fitted parameters.
struct MarkerPlacement {
  double local_x_m = 0, local_y_m = 0;    // l, m
  double camera_x_m = 0, camera_y_m = 0;  // c, m
};

inline MarkerPlacement PlaceMarker(const VirtualLayer& layer, double col, double row, double camera_x,
                                   double camera_y) {
  const PanelSpec& p = layer.panel;
  const double x =
      (col - static_cast<double>(p.active_left) + 0.5 - 0.5 * static_cast<double>(p.active_cols)) * p.pitch_x_m;
  const double y =
      (0.5 * static_cast<double>(p.active_rows) - (row - static_cast<double>(p.active_top)) - 0.5) * p.pitch_y_m;
  return {layer.flip_x ? -x : x, layer.flip_y ? -y : y, camera_x, camera_y};
}

// The elements with power on a layer's path, nearest the eye first: for each,
// its index among the fit's elements and c_i (m), the path length before its
// gap that no fitted gap covers.
struct LayerOptics {
  std::vector<int> element;
  std::vector<double> fixed_spacing;
};

// The fitted parameters of the model for one layer, by role.
template <typename T>
struct MarkerParameters {
  T distance, eye_from_panel_x_m, eye_from_panel_y_m, rotation;
  T pan, tilt, roll;
  std::vector<T> gaps, focal_lengths, distortions;  // of LayerOptics' elements, in its order
};

// Pupil -> panel: the one composition every fitted layer goes through.
template <typename T>
RayTransfer<T> LayerTransfer(const LayerOptics& optics, const MarkerParameters<T>& q) {
  RayTransfer<T> m;
  for (size_t i = 0; i < optics.fixed_spacing.size(); ++i)
    m = m.then_gap(T(optics.fixed_spacing[i]) + q.gaps[i]).then_power(T(1) / q.focal_lengths[i]);
  return m.then_gap(q.distance);
}

template <typename T>
void PredictVisualAngle(const MarkerParameters<T>& q, const LayerOptics& optics, const MarkerPlacement& m, T angle[2]) {
  using std::abs;
  using std::atan;
  using std::cos;
  using std::sin;
  const RayTransfer<T> transfer = LayerTransfer(optics, q);
  const T tan_per_meter = T(1) / abs(transfer.b);
  const T diopters = transfer.diopters();
  const T c = cos(q.rotation), s = sin(q.rotation);
  const T x = q.eye_from_panel_x_m + c * m.local_x_m - s * m.local_y_m;
  const T y = q.eye_from_panel_y_m + s * m.local_x_m + c * m.local_y_m;
  T distortion(0);
  for (const T& k : q.distortions) distortion += k;
  const T radial = T(1) + distortion * tan_per_meter * tan_per_meter * (x * x + y * y);
  const T eye_direction[3] = {tan_per_meter * x * radial - m.camera_x_m * diopters,
                              tan_per_meter * y * radial - m.camera_y_m * diopters, T(1)};
  const T camera_from_eye[3] = {q.tilt, -q.pan, -q.roll};  // the inverse of R_cam
  T d[3];
  ceres::AngleAxisRotatePoint(camera_from_eye, eye_direction, d);
  angle[0] = atan(d[0] / d[2]);
  angle[1] = atan(d[1] / d[2]);
}

}  // namespace layerlab
