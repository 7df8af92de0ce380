// A point of the eye's pupil and the radiance a scene sends along a ray from
// it: what a retinal image is made of (retina.h), and what a traced target
// hands the retinal objective (solvers/types.h), without either's machinery.
#pragma once

#include <array>
#include <functional>

namespace layerlab {

struct PupilPoint {
  double x_m = 0, y_m = 0;          // m, on the pupil plane
  double slope_x = 0, slope_y = 0;  // the eye's wavefront slope there (elements/wavefront.h): every
                                    // ray from this point leaves along the ideal direction minus it
};

// Natural viewing: the radiance along the ray from a pupil point with tan-direction
// (dx, dy) (the ray passes (x + dx z, y + dy z, z) at depth z).
using SceneRadiance = std::function<std::array<double, 3>(const PupilPoint& origin, double dx, double dy)>;

}  // namespace layerlab
