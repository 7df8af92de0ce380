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

  const float* pattern_a = (*t)[layer].rgb.data();
  const bool one_tap = P.separable() && P.sampling() == Sampling::kNearest;

#pragma omp parallel
  {
    // Reused across calls: a paper-scale update would otherwise fault in megabytes of fresh pages.
    thread_local std::vector<float> rest, sampled, target_scratch;
    // A pixel's sums run over the few rays per view that reach it, at most a few
    // hundred per thread: float is exact enough there, and the merge is in double.
    thread_local std::vector<float> num, den;
    rest.resize(n), sampled.resize(n), target_scratch.resize(n);
    num.assign(m, 0.0f), den.assign(m, 0.0f);
#pragma omp for schedule(dynamic)
    for (size_t v = 0; v < g.view_count(); ++v) {
      for (size_t k = 0; k < n; k += 3) rest[k] = w[0], rest[k + 1] = w[1], rest[k + 2] = w[2];
      for (int other : layers)
        if (other != layer) model.projection(other).GatherMultiply(v, (*t)[other].rgb.data(), rest.data());
      const float* target = branch_target(v, target_scratch.data());
      // One pass over the rays: numerator P^T(r o Q), denominator P^T((P t) o Q o Q).
      if (one_tap) {
        P.ForEachTap(v, [&](size_t ray, int32_t pixel, float) {
          const float* q = &rest[ray * 3];
          const float* r = &target[ray * 3];
          const float* s = &pattern_a[static_cast<size_t>(pixel) * 3];
          float* nu = &num[static_cast<size_t>(pixel) * 3];
          float* de = &den[static_cast<size_t>(pixel) * 3];
          for (int c = 0; c < 3; ++c) {
            nu[c] += r[c] * q[c];
            de[c] += s[c] * q[c] * q[c];
          }
        });
      } else {
        P.Gather(v, pattern_a, sampled.data());
        P.ForEachTap(v, [&](size_t ray, int32_t pixel, float weight) {
          for (int c = 0; c < 3; ++c) {
            const float q = rest[ray * 3 + c];
            num[static_cast<size_t>(pixel) * 3 + c] += weight * target[ray * 3 + c] * q;
            den[static_cast<size_t>(pixel) * 3 + c] += weight * sampled[ray * 3 + c] * q * q;
          }
        });
      }
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
