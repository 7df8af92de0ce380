#include "layerlab/analysis/fourier.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>

#include "layerlab/framework/error.h"

namespace layerlab {

double FourierAmplitude(const std::vector<double>& values, const std::vector<double>& degrees,
                        double cycles_per_degree) {
  if (values.size() != degrees.size() || values.empty()) throw Error("FourierAmplitude: mismatched samples");
  std::complex<double> sum = 0;
  for (size_t k = 0; k < values.size(); ++k)
    sum += values[k] * std::polar(1.0, -2 * std::numbers::pi * cycles_per_degree * degrees[k]);
  return 2.0 * std::abs(sum) / values.size();
}

int WholeCycleSamples(int count, double resolution_deg, double cycles_per_degree) {
  double samples_per_cycle = 1.0 / (cycles_per_degree * resolution_deg);
  int cycles = static_cast<int>(std::floor(count / samples_per_cycle + 1e-9));
  return std::max(1, static_cast<int>(std::lround(cycles * samples_per_cycle)));
}

Peak FindPeak(const std::vector<double>& x, const std::vector<double>& y) {
  if (x.empty() || x.size() != y.size()) throw Error("FindPeak: mismatched samples");
  size_t k = std::max_element(y.begin(), y.end()) - y.begin();
  Peak p{x[k], x[k], y[k]};
  if (k == 0 || k + 1 == x.size()) return p;
  // Vertex of the parabola through three equally spaced samples.
  double denominator = y[k - 1] - 2 * y[k] + y[k + 1];
  if (denominator < 0) p.at_parabola = x[k] + 0.5 * (x[k + 1] - x[k]) * (y[k - 1] - y[k + 1]) / denominator;
  return p;
}

PeakEstimate EstimatePeak(const std::vector<double>& x, const std::vector<double>& y,
                          const std::vector<double>& y_other, double flat_limit) {
  if (!y_other.empty() && y_other.size() != y.size()) throw Error("EstimatePeak: mismatched samples");
  auto placeable = [](const std::vector<double>& v) {
    const size_t top = std::max_element(v.begin(), v.end()) - v.begin();
    return top > 0 && top + 1 < v.size() && v[top - 1] - 2 * v[top] + v[top + 1] < 0;
  };
  PeakEstimate e;
  e.at = FindPeak(x, y).at_parabola;
  e.flat = !placeable(y);
  if (!y_other.empty()) {
    e.uncertainty = std::abs(FindPeak(x, y_other).at_parabola - e.at);
    e.flat = e.flat || !placeable(y_other) || e.uncertainty > flat_limit * (1 + 1e-9);
  }
  return e;
}

}  // namespace layerlab
