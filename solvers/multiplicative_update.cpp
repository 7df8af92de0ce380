#include "solvers/multiplicative_update.h"

#include <algorithm>
#include <vector>

namespace layerlab {

void UpdateLayerMultiplicative(const DisplayModel& model, size_t branch, int layer, const BranchTarget& branch_target,
                               const SolverOptions& options, Patterns* t) {
  const LightFieldGeometry& g = model.geometry();
  const LayerProjection& P = model.projection(layer);
  const std::vector<int>& layers = model.branch_layers(branch);
  const std::array<float, 3> w = model.weight(branch);
  const size_t n = g.pixels_per_view() * 3;
  const size_t m = P.pixel_count() * 3;
  std::vector<double> numerator(m, 0.0), denominator(m, 0.0);

#pragma omp parallel
  {
    std::vector<float> rest(n), sampled(n), target_scratch(n), scratch(n);
    std::vector<double> num(m, 0.0), den(m, 0.0);
#pragma omp for schedule(dynamic)
    for (size_t v = 0; v < g.view_count(); ++v) {
      for (size_t k = 0; k < n; ++k) rest[k] = w[k % 3];
      for (int other : layers)
        if (other != layer) model.projection(other).GatherMultiply(v, (*t)[other].rgb.data(), rest.data());
      P.Gather(v, (*t)[layer].rgb.data(), sampled.data());
      const float* target = branch_target(v, target_scratch.data());
      for (size_t k = 0; k < n; ++k) {
        scratch[k] = target[k] * rest[k];          // r o Q
        sampled[k] = sampled[k] * rest[k] * rest[k];  // l~_b o Q
      }
      P.ScatterAdd(v, scratch.data(), num.data());
      P.ScatterAdd(v, sampled.data(), den.data());
    }
#pragma omp critical
    for (size_t k = 0; k < m; ++k) {
      numerator[k] += num[k];
      denominator[k] += den[k];
    }
  }

  std::vector<float>& pattern = (*t)[layer].rgb;
  const float floor = static_cast<float>(options.floor);
  for (size_t k = 0; k < m; ++k) {
    if (!(denominator[k] > options.epsilon)) continue;
    double updated = pattern[k] * (numerator[k] / denominator[k]);
    // NaN fails both comparisons and lands on the floor rather than passing through.
    pattern[k] = updated >= 1.0 ? 1.0f : updated > floor ? static_cast<float>(updated) : floor;
  }
}

}  // namespace layerlab
