#include "layerlab/eye/contrast_sensitivity.h"

#include <cmath>

namespace layerlab {
namespace {

double MannosSakrison(double f) { return 2.6 * (0.0192 + 0.114 * f) * std::exp(-std::pow(0.114 * f, 1.1)); }

// dS/df = 0 where 0.114 (1 - 1.1 (0.114 f)^1.1 (0.0192 + 0.114 f) / (0.114 f)) = 0; found by bisection once.
double FindPeak() {
  double lo = 1, hi = 30;
  for (int k = 0; k < 100; ++k) {
    const double mid = (lo + hi) / 2, h = 1e-6 * mid;
    (MannosSakrison(mid + h) > MannosSakrison(mid - h) ? lo : hi) = mid;
  }
  return (lo + hi) / 2;
}

}  // namespace

double ContrastSensitivityPeak() {
  static const double peak = FindPeak();
  return peak;
}

double ContrastSensitivityWeight(double f) {
  const double peak = ContrastSensitivityPeak();
  if (f <= peak) return 1;
  return MannosSakrison(f) / MannosSakrison(peak);
}

}  // namespace layerlab
