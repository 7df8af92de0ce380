#include "layerlab/metrics/foveal_weight.h"

#include <cmath>
#include <string>

#include "layerlab/framework/error.h"

namespace layerlab {

double FovealWeightAt(double eccentricity_deg) {
  const double r = kFovealE2Deg / (eccentricity_deg + kFovealE2Deg);
  return r * r;
}

Plane FovealWeight(int width, int height, double pixel_deg, double gaze_x_deg, double gaze_y_deg) {
  if (width < 1 || height < 1) throw Error("foveal weight: an empty image");
  if (!(pixel_deg > 0) || !std::isfinite(pixel_deg))
    throw Error("foveal weight: pixel_deg " + std::to_string(pixel_deg) + ": must be above 0");
  if (!std::isfinite(gaze_x_deg) || !std::isfinite(gaze_y_deg)) throw Error("foveal weight: a gaze that is not finite");
  Plane w{width, height, std::vector<double>(size_t(width) * height)};
  for (int i = 0; i < height; ++i)
    for (int j = 0; j < width; ++j) {
      const double x = (j + 0.5 - 0.5 * width) * pixel_deg - gaze_x_deg;
      const double y = (0.5 * height - i - 0.5) * pixel_deg - gaze_y_deg;
      w.values[size_t(i) * width + j] = FovealWeightAt(std::hypot(x, y));
    }
  return w;
}

}  // namespace layerlab
