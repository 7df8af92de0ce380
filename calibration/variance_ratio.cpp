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
  // Paulson: (A F^(1/3) - B) / sqrt(a + b F^(2/3)) is nearly a standard normal
  // (Wilson and Hilferty's cube root of each chi-square); solved for F^(1/3)
  // at z, the larger root of (A^2 - z^2 b) u^2 - 2 A B u + (B^2 - z^2 a) = 0.
  const double z = NormalUpperQuantile(level);
  const double a = 2.0 / (9.0 * d1), b = d2 > 0 ? 2.0 / (9.0 * d2) : 0.0;
  const double A = 1 - b, B = 1 - a;
  const double quadratic = A * A - z * z * b, half_linear = A * B, constant = B * B - z * z * a;
  const double u = (half_linear + std::sqrt(half_linear * half_linear - quadratic * constant)) / quadratic;
  return u * u * u;
}

}  // namespace layerlab
