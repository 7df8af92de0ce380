#include "layerlab/elements/eye_pose.h"

#include <cmath>

namespace layerlab {

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

}  // namespace layerlab
