#include "layerlab/systems/world_view.h"

#include <limits>

#include "layerlab/framework/polarization.h"

namespace layerlab {

Rgb WorldAtEye(const DisplaySystem& system) {
  Rgb sum{};
  for (const WorldView& w : system.worlds)
    for (int c = 0; c < 3; ++c) sum[c] += w.luminance_cd_m2 * w.efficiency[c];
  return sum;
}

double LuminanceOf(const Rgb& rgb) {
  double y = 0;
  for (int c = 0; c < 3; ++c) y += kLuminanceWeights[c] * rgb[c];
  return y;
}

double AmbientContrastRatio(const DisplaySystem& system) {
  const double world = LuminanceOf(WorldAtEye(system));
  if (!(world > 0)) return std::numeric_limits<double>::infinity();
  return (LuminanceOf(system.peak_luminance_cd_m2) + world) / world;
}

}  // namespace layerlab
