// A point of the eye's pupil and the radiance a scene sends along a ray from
// it: what a retinal image is made of (retina.h), and what a traced target
// hands the retinal objective (solvers/types.h), without either's machinery.
#pragma once

#include <array>
#include <functional>

namespace layerlab {

struct PupilPoint {
  double x_m = 0, y_m = 0;                // m, where its rays cross the eye plane (elements/eye_pose.h)
  double slope_x = 0, slope_y = 0;        // the eye's wavefront slope there (elements/wavefront.h): every
                                          // ray from this point leaves along the ideal direction minus it
  double center_x_m = 0, center_y_m = 0;  // m, the pupil's centre on the eye plane (0 for an eye on the axis)
  // The ray toward retinal direction tan with the eye focused at `focus`
  // diopters aims at the in-focus point center + tan / focus, so it leaves
  // with tan-direction tan - x focus - deviation(focus).
  double deviation_x(double focus) const { return slope_x - center_x_m * focus; }
  double deviation_y(double focus) const { return slope_y - center_y_m * focus; }
};

// Natural viewing: the radiance along the ray from a pupil point with tan-direction
// (dx, dy) (the ray passes (x + dx z, y + dy z, z) at depth z).
using SceneRadiance = std::function<std::array<double, 3>(const PupilPoint& origin, double dx, double dy)>;

}  // namespace layerlab
