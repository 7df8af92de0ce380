#include "layerlab/systems/eye_pose_limits.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "layerlab/framework/error.h"
#include "layerlab/framework/units.h"

namespace layerlab {

EyeModel PartnerEye(const EyeModel& eye) {
  if (!eye.binocular) throw Error("the scene's eye is not one of a binocular pair (its \"binocular\" key)");
  EyeModel other = eye;
  other.binocular->side = -eye.binocular->side;
  other.pose = FixatingPose(*other.binocular, eye.pose.rotation_radius_m);
  return other;
}

std::array<double, 2> GazeAngles(const EyePose& pose) {
  const Vector3 g = GazeDirection(pose);
  return {std::atan(g[0] / g[2]), std::atan(g[1] / g[2])};
}

std::string GazeBeyondField(const DisplaySystem& system, const EyePose& pose) {
  const std::array<double, 2> angle = GazeAngles(pose);
  const std::array<double, 2> half = {0.5 * system.fov_x_rad, 0.5 * system.fov_y_rad};
  const char* side[2][2] = {{"left", "right"}, {"down", "up"}};
  for (int a = 0; a < 2; ++a)
    if (std::abs(angle[a]) > half[a] * (1 + 1e-12))
      return FormatFixed(std::abs(angle[a]) * kDegreesPerRadian, 2) + " deg " + side[a][angle[a] > 0] +
             " is beyond the display's field, " + FormatFixed(half[a] * kDegreesPerRadian, 2) +
             " deg either side of the axis";
  return "";
}

std::array<double, 2> PupilReachOnEyePlane(const EyeModel& eye) {
  const double r = 0.5 * eye.pupil_diameter_m;
  std::array<double, 2> reach = {0, 0};
  auto take = [&](double u_x, double u_y) {
    const std::array<double, 2> at = OnEyePlane(eye.pose, u_x, u_y);
    reach = {std::max(reach[0], std::abs(at[0])), std::max(reach[1], std::abs(at[1]))};
  };
  if (eye.pupil_shape == PupilShape::kSquare) {
    for (double u_x : {-r, r})
      for (double u_y : {-r, r}) take(u_x, u_y);  // the map to the eye plane is affine: corners bound it
  } else {
    const int n = 720;
    for (int k = 0; k < n; ++k) {
      const double phi = 2 * std::numbers::pi * k / n;
      take(r * std::cos(phi), r * std::sin(phi));
    }
  }
  return reach;
}

std::string PupilBeyondEyebox(const EyeModel& eye) {
  const std::array<double, 2> reach = PupilReachOnEyePlane(eye);
  const std::array<double, 2> half = {0.5 * eye.eyebox_width_m, 0.5 * eye.eyebox_height_m};
  const double tolerance = 1e-12;
  for (int a = 0; a < 2; ++a)
    if (reach[a] > half[a] + tolerance) {
      const double room = std::max(0.0, half[a] - (reach[a] - std::abs(OnEyePlane(eye.pose, 0, 0)[a])));
      return "the pupil reaches " + FormatFixed(reach[a] * 1e3, 3) + " mm from the axis in " + (a ? "y" : "x") +
             ", beyond the eyebox's " + FormatFixed(half[a] * 1e3, 3) + " mm (its " +
             FormatFixed(eye.pupil_diameter_m * 1e3, 2) + " mm pupil stays inside up to " + FormatFixed(room * 1e3, 3) +
             " mm off the axis; a wider eyebox needs a light field with wider views)";
    }
  return "";
}

std::string PupilBeyondEyeboxWarning(const EyeModel& eye) {
  const std::string beyond = PupilBeyondEyebox(eye);
  return beyond.empty() ? "" : beyond + ": natural viewing reads the edge views there";
}

}  // namespace layerlab
