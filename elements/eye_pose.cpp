#include "layerlab/elements/eye_pose.h"

#include <cmath>
#include <string>

#include "layerlab/framework/error.h"
#include "layerlab/framework/option_table.h"
#include "layerlab/framework/units.h"

namespace layerlab {

namespace {

// n, the whole steps within the range; -1 for a zero range.
double EyeboxGridHalf(double range_m, double step_m) {
  if (!(range_m > 0)) return -1;
  return std::floor(range_m / (step_m > 0 ? step_m : range_m) * (1 + 1e-12));
}

}  // namespace

double EyeboxGridSize(double range_m, double step_m) {
  const double n = EyeboxGridHalf(range_m, step_m);
  return n < 0 ? 0 : (2 * n + 1) * (2 * n + 1);
}

std::vector<std::array<double, 2>> EyeboxGridOffsets(double range_m, double step_m) {
  if (EyeboxGridSize(range_m, step_m) > kMaxEyeboxGridSize)
    throw Error("an eyebox grid of more than " + std::to_string(kMaxEyeboxGridSize) + " pupil positions");
  std::vector<std::array<double, 2>> offsets;
  const int half = int(EyeboxGridHalf(range_m, step_m));
  const double step = step_m > 0 ? step_m : range_m;
  for (int j = -half; j <= half; ++j)
    for (int i = -half; i <= half; ++i) offsets.push_back({i * step, j * step});
  return offsets;
}

std::string EyeboxGridViolation(double range_m, double step_m, int max_positions, const std::string& why_limited) {
  if (!(range_m > 0))
    return step_m > 0 ? "eyebox_step: describes the eyebox grid of eyebox_range, which is 0 (the eye's pupil alone)"
                      : "";
  if (step_m > range_m)
    return OptionViolation("eyebox_step", step_m, "must be at most eyebox_range (" + FormatGeneral(range_m) + ")");
  if (const double n = EyeboxGridSize(range_m, step_m); n > max_positions)
    return OptionViolation("eyebox_step", step_m,
                           "makes a grid of " + FormatGeneral(n) + " pupil positions, more than " +
                               std::to_string(max_positions) + why_limited);
  return "";
}

EyePose WithPupilMoved(EyePose pose, double dx_m, double dy_m) {
  pose.pupil_offset_m[0] += dx_m;
  pose.pupil_offset_m[1] += dy_m;
  return pose;
}

Vector3 PairFrameInDisplayFrame(const Binocular& b) {
  return {b.shared_display ? 0.0 : -b.side * b.ipd_m / 2, 0.0, 0.0};
}

Vector3 GazeDirection(const EyePose& pose) {
  const double cx = std::cos(pose.gaze_rad[0]), sx = std::sin(pose.gaze_rad[0]);
  const double cy = std::cos(pose.gaze_rad[1]), sy = std::sin(pose.gaze_rad[1]);
  return {sx * cy, sy, cx * cy};
}

Vector3 PupilCenter(const EyePose& pose) {
  const Vector3 g = GazeDirection(pose);
  const double r = pose.rotation_radius_m;
  return {pose.pupil_offset_m[0] + r * g[0], pose.pupil_offset_m[1] + r * g[1], r * (g[2] - 1)};
}

Vector3 PupilPointAt(const EyePose& pose, double u_x, double u_y) {
  const double cx = std::cos(pose.gaze_rad[0]), sx = std::sin(pose.gaze_rad[0]);
  const double cy = std::cos(pose.gaze_rad[1]), sy = std::sin(pose.gaze_rad[1]);
  const Vector3 axis_x = {cx, 0, -sx}, axis_y = {-sx * sy, cy, -cx * sy};  // the turned x and y axes
  const Vector3 c = PupilCenter(pose);
  return {c[0] + u_x * axis_x[0] + u_y * axis_y[0], c[1] + u_x * axis_x[1] + u_y * axis_y[1],
          c[2] + u_x * axis_x[2] + u_y * axis_y[2]};
}

std::array<double, 2> OnEyePlane(const EyePose& pose, double u_x, double u_y) {
  if (pose.straight_ahead()) return {pose.pupil_offset_m[0] + u_x, pose.pupil_offset_m[1] + u_y};
  const Vector3 g = GazeDirection(pose), p = PupilPointAt(pose, u_x, u_y);
  return {p[0] - p[2] * g[0] / g[2], p[1] - p[2] * g[1] / g[2]};
}

namespace {

// F - Q for the eye on `side`.
Vector3 ToFixation(const Binocular& b, int side, double rotation_radius_m) {
  const double x_eye = 0.5 * side * b.ipd_m;
  return {b.fixation_m[0] - x_eye, b.fixation_m[1], b.fixation_m[2] + rotation_radius_m};
}

}  // namespace

EyePose FixatingPose(const Binocular& b, double rotation_radius_m) {
  const Vector3 v = ToFixation(b, b.side, rotation_radius_m);
  EyePose pose;
  pose.rotation_radius_m = rotation_radius_m;
  if (b.shared_display) pose.pupil_offset_m = {0.5 * b.side * b.ipd_m, 0};
  pose.gaze_rad = {std::atan2(v[0], v[2]), std::atan2(v[1], std::hypot(v[0], v[2]))};
  return pose;
}

double VergenceAngle(const Binocular& b, double rotation_radius_m) {
  const Vector3 l = ToFixation(b, -1, rotation_radius_m), r = ToFixation(b, 1, rotation_radius_m);
  const double dot = l[0] * r[0] + l[1] * r[1] + l[2] * r[2];
  const double cross = std::hypot(l[1] * r[2] - l[2] * r[1], l[2] * r[0] - l[0] * r[2], l[0] * r[1] - l[1] * r[0]);
  return std::atan2(cross, dot);
}

double VergenceDiopters(const Binocular& b) {
  return 1 / std::hypot(b.fixation_m[0], b.fixation_m[1], b.fixation_m[2]);
}

}  // namespace layerlab
