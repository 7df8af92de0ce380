#include "layerlab/calibration/variance_ratio.h"

#include <cmath>

namespace layerlab {

double NormalUpperQuantile(double upper_tail) {
  // Bisection on the tail 0.5 erfc(z / sqrt 2), which falls monotonically; 200 halvings reach double precision.
  double low = -40, high = 40;
  for (int k = 0; k < 200; ++k) {
    const double z = 0.5 * (low + high);
    if (0.5 * std::erfc(z / std::sqrt(2.0)) > upper_tail)
      low = z;
    else
      high = z;
  }
  return 0.5 * (low + high);
}

double CriticalVarianceRatio(int d1, int d2, double level) {
  const double inverse_d1 = 1.0 / d1, inverse_d2 = d2 > 0 ? 1.0 / d2 : 0.0;
  const double mean = 0.5 * (inverse_d2 - inverse_d1), variance = 0.5 * (inverse_d1 + inverse_d2);
  return std::exp(2 * (mean + NormalUpperQuantile(level) * std::sqrt(variance)));
}

}  // namespace layerlab
