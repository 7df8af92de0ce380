#include "solvers/multiplicative_update.h"

#include <algorithm>
#include <vector>

namespace layerlab {
namespace {

// Per-thread sums over the rays of the views a thread takes. A pixel's sums
// run over the few rays per view that reach it, at most a few hundred per
// thread: float is exact enough there, and the merge across threads is in double.
struct Sums {
  std::vector<float> num, den;
};

// Every layer of the branch reads one pixel per ray (nearest sampling, no
// rotation): one pass over the rays of a view, row by row, with the rest of
// the branch multiplied on the fly, so nothing of view size is stored.
void AccumulateOneTap(const DisplayModel& model, const std::vector<int>& layers, int layer, const Patterns& t,
                      const std::array<float, 3>& w, size_t view, const float* target, Sums* sums) {
  const LightFieldGeometry& g = model.geometry();
  const LayerProjection& P = model.projection(layer);
  struct Other {
    const AxisTap* rows;
    const AxisTap* cols;
    const float* pattern;
    int cols_count;
    const float* row = nullptr;  // the pattern row of the current ray row
  };
  std::vector<Other> others;  // small: the branch's other layers
  for (int k : layers)
    if (k != layer) {
      const LayerProjection& Q = model.projection(k);
      others.push_back({Q.row_taps(view), Q.col_taps(view), t[k].rgb.data(), Q.cols()});
    }
  const AxisTap* rows_a = P.row_taps(view);
  const AxisTap* cols_a = P.col_taps(view);
  const float* pattern_a = t[layer].rgb.data();
  float* num = sums->num.data();
  float* den = sums->den.data();

  for (int i = 0; i < g.rows; ++i) {
    if (rows_a[i].i0 < 0) continue;
    bool dark = false;  // some other layer misses this whole row: the rest of the branch is 0
    for (Other& o : others) {
      if (o.rows[i].i0 < 0) dark = true;
      else o.row = o.pattern + static_cast<size_t>(o.rows[i].i0) * o.cols_count * 3;
    }
    if (dark) continue;
    const size_t row_a = static_cast<size_t>(rows_a[i].i0) * P.cols();
    const float* r = target + static_cast<size_t>(i) * g.cols * 3;
    for (int j = 0; j < g.cols; ++j, r += 3) {
      if (cols_a[j].i0 < 0) continue;
      float q0 = w[0], q1 = w[1], q2 = w[2];
      for (const Other& o : others) {
        const int32_t c = o.cols[j].i0;
        if (c < 0) {
          q0 = q1 = q2 = 0;
          break;
        }
        const float* p = o.row + static_cast<size_t>(c) * 3;
        q0 *= p[0], q1 *= p[1], q2 *= p[2];
      }
      const size_t pixel = (row_a + cols_a[j].i0) * 3;
      const float* s = pattern_a + pixel;
      num[pixel] += r[0] * q0;
      num[pixel + 1] += r[1] * q1;
      num[pixel + 2] += r[2] * q2;
      den[pixel] += s[0] * q0 * q0;
      den[pixel + 1] += s[1] * q1 * q1;
      den[pixel + 2] += s[2] * q2 * q2;
    }
  }
}

// Any layers: the rest of the branch per view into a buffer, then one pass over the taps.
void AccumulateGeneral(const DisplayModel& model, const std::vector<int>& layers, int layer, const Patterns& t,
                       const std::array<float, 3>& w, size_t view, const float* target, Sums* sums) {
  const size_t n = model.geometry().pixels_per_view() * 3;
  const LayerProjection& P = model.projection(layer);
  thread_local std::vector<float> rest, sampled;
  rest.resize(n), sampled.resize(n);
  for (size_t k = 0; k < n; k += 3) rest[k] = w[0], rest[k + 1] = w[1], rest[k + 2] = w[2];
  for (int other : layers)
    if (other != layer) model.projection(other).GatherMultiply(view, t[other].rgb.data(), rest.data());
  P.Gather(view, t[layer].rgb.data(), sampled.data());
  P.ForEachTap(view, [&](size_t ray, int32_t pixel, float weight) {
    for (int c = 0; c < 3; ++c) {
      const float q = rest[ray * 3 + c];
      sums->num[static_cast<size_t>(pixel) * 3 + c] += weight * target[ray * 3 + c] * q;
      sums->den[static_cast<size_t>(pixel) * 3 + c] += weight * sampled[ray * 3 + c] * q * q;
    }
  });
}

}  // namespace

void UpdateLayerMultiplicative(const DisplayModel& model, size_t branch, int layer, const BranchTarget& branch_target,
                               const SolverOptions& options, Patterns* t) {
  const LightFieldGeometry& g = model.geometry();
  const std::vector<int>& layers = model.branch_layers(branch);
  const std::array<float, 3> w = model.weight(branch);
  const size_t n = g.pixels_per_view() * 3;
  const size_t m = model.projection(layer).pixel_count() * 3;
  const bool one_tap = std::all_of(layers.begin(), layers.end(), [&](int k) { return model.projection(k).one_tap(); });
  // Reused across calls (fresh megabytes would be page-faulted in on every update).
  thread_local std::vector<double> numerator_memory, denominator_memory;
  numerator_memory.assign(m, 0.0), denominator_memory.assign(m, 0.0);
  double* numerator = numerator_memory.data();  // the calling thread's, shared with the workers
  double* denominator = denominator_memory.data();

#pragma omp parallel
  {
    thread_local Sums sums;
    thread_local std::vector<float> target_scratch;
    sums.num.assign(m, 0.0f), sums.den.assign(m, 0.0f);
    target_scratch.resize(n);
#pragma omp for schedule(dynamic)
    for (size_t v = 0; v < g.view_count(); ++v) {
      const float* target = branch_target(v, target_scratch.data());
      if (one_tap)
        AccumulateOneTap(model, layers, layer, *t, w, v, target, &sums);
      else
        AccumulateGeneral(model, layers, layer, *t, w, v, target, &sums);
    }
#pragma omp critical
    for (size_t k = 0; k < m; ++k) {
      numerator[k] += sums.num[k];
      denominator[k] += sums.den[k];
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
