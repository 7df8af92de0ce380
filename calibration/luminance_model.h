// A panel's luminance against its input level x in [0, 1] (8-bit codes / 255):
//   L(x) = L_max (b + (1 - b) x^gamma),
// b the black level relative to the maximum (PanelSpec::black_level) and gamma
// the panel's exponent (PanelSpec::gamma). Templated for Ceres.
#pragma once

#include <cmath>

namespace layerlab {

template <typename T>
T ModelLuminance(double level, const T& max_luminance, const T& black_level, const T& gamma) {
  using std::pow;
  // x^gamma at x = 0 is written out: pow's derivative in gamma there is 0 * log(0).
  const T shape = level > 0 ? T(pow(level, gamma)) : T(0);
  return max_luminance * (black_level + (T(1) - black_level) * shape);
}

}  // namespace layerlab
