#include "layerlab/kernels/layer_update_sums.h"

#include <omp.h>

#include <algorithm>
#include <vector>

#include "layerlab/framework/fixed_parts.h"
#include "layerlab/framework/mpi_ranks.h"
#include "layerlab/kernels/one_tap_update.h"
#include "layerlab/kernels/one_tap_view.h"
#include "layerlab/kernels/thread_merge.h"

namespace layerlab {
namespace {

// With one tap of weight 1 per ray (the one-tap path), w_b and layer a's own
// value are the same for every ray a pixel sums, so OneTapUpdateSums leaves
// them out:  num = w_b sum r q,  den = w_b^2 t_a sum q^2.  They go back here.
void FinishOneTapSums(const std::array<float, 3>& w, const std::vector<float>& t_a, double* num, double* den) {
#pragma omp parallel for schedule(static)
  for (size_t p = 0; p < t_a.size(); p += 3)
    for (int c = 0; c < 3; ++c) {
      num[p + c] *= w[c];
      den[p + c] *= double(w[c]) * w[c] * t_a[p + c];
    }
}

// Any layers: the rest of the branch per view into a buffer, then one pass
// over the taps into this thread's float sums of the layer (w->num, w->den).
// A pixel's sums run over the few rays per view that reach it, at most a few
// hundred per thread: float is exact enough there, and the merge across
// threads is in double.
void AccumulateGeneral(const DisplayModel& model, const std::vector<int>& layers, int layer, const Patterns& t,
                       const std::array<float, 3>& w, size_t view, const float* target, ThreadWorkspace* ws) {
  const size_t n = model.geometry().pixels_per_view() * 3;
  const LayerProjection& P = model.projection(layer);
  std::vector<float>&rest = ws->rest, &sampled = ws->sampled;
  float* num = ws->num[layer].data();
  float* den = ws->den[layer].data();
  rest.resize(n), sampled.resize(n);
  for (size_t k = 0; k < n; k += 3) rest[k] = w[0], rest[k + 1] = w[1], rest[k + 2] = w[2];
  for (int other : layers)
    if (other != layer) model.projection(other).GatherMultiply(view, t[other].rgb.data(), rest.data(), &ws->gathered);
  P.Gather(view, t[layer].rgb.data(), sampled.data());
  P.ForEachChannelTap(view, [&](size_t ray, int c, int32_t pixel, float weight) {
    const float q = rest[ray * 3 + c];
    num[static_cast<size_t>(pixel) * 3 + c] += weight * target[ray * 3 + c] * q;
    den[static_cast<size_t>(pixel) * 3 + c] += weight * sampled[ray * 3 + c] * q * q;
  });
}

}  // namespace

bool ComputeLayerUpdate(const DisplayModel& model, BranchLayer which, const BranchTarget& branch_target,
                        const Patterns& t, SolveWorkspace* workspace, LayerUpdate* update, double* error) {
  const size_t branch = which.branch;
  const int layer = which.layer;
  const LightFieldGeometry& g = model.geometry();
  const std::vector<int>& layers = model.branch_layers(branch);
  const std::array<float, 3> w = model.weight(branch);
  const size_t n = g.pixels_per_view() * 3;
  const size_t m = model.projection(layer).pixel_count() * 3;
  const bool one_tap = OneTapBranch(model, branch);
  update->branch = branch, update->layer = layer;
  update->num->resize(m), update->den->resize(m);  // written whole by the merge
  double* numerator = update->num->data();
  double* denominator = update->den->data();

  if (one_tap) {
    std::vector<int> a_first{layer};
    for (int k : layers)
      if (k != layer) a_first.push_back(k);
    std::vector<double>& view_errors = workspace->view_errors;
    view_errors.assign(error ? g.view_count() : 0, 0.0);
    OneTapUpdateSums(model, {a_first, w}, t, branch_target,
                     {numerator, denominator, error ? view_errors.data() : nullptr}, workspace);
    FinishOneTapSums(w, t[layer].rgb, numerator, denominator);
    if (error) {
      *error = 0;
      for (double e : view_errors) *error += e;  // in view order: the same for any thread count
    }
    SumAcrossRanks({*update->num, *update->den, {error, error ? 1u : 0u}});
    return error != nullptr;
  }
  // Views cut into the workspace's fixed parts, merged in part order (framework/fixed_parts.h).
  const int parts = workspace->threads();
  std::vector<const float*> nums(parts), dens(parts);  // [part]
#pragma omp parallel
  {
    ForEachPartOfThread(parts, [&](int p) {
      ThreadWorkspace& ws = workspace->thread(p);
      ws.num[layer].assign(m, 0.0f), ws.den[layer].assign(m, 0.0f);
      ws.target.resize(n);
      nums[p] = ws.num[layer].data(), dens[p] = ws.den[layer].data();
      const ItemRange views = StaticShare(g.view_count(), p, parts);
      for (size_t v = views.begin; v < views.end; ++v)
        AccumulateGeneral(model, layers, layer, t, w, v, branch_target(v, ws.target.data()), &ws);
    });
#pragma omp barrier
    const int threads = omp_get_num_threads(), me = omp_get_thread_num();
    MergeInThreadOrder(nums, m / 3, 3, me, threads, numerator);
    MergeInThreadOrder(dens, m / 3, 3, me, threads, denominator);
  }
  SumAcrossRanks({*update->num, *update->den});
  return false;
}

void ComputeLayerUpdateFromPairs(const DisplayModel& model, BranchLayer which, const PairLattice& lattice,
                                 const PairCells& binned, const Patterns& t, SolveWorkspace* workspace,
                                 LayerUpdate* update) {
  const size_t branch = which.branch;
  const int layer = which.layer;
  const size_t m = model.projection(layer).pixel_count() * 3;
  const int other = lattice.other_layer(layer);
  workspace->padded.Pad(t, {other});
  update->branch = branch, update->layer = layer;
  update->num->resize(m), update->den->resize(m);
  lattice.UpdateSums(layer, workspace->padded.pixels(other), binned, update->num->data(), update->den->data());
  FinishOneTapSums(model.weight(branch), t[layer].rgb, update->num->data(), update->den->data());
  SumAcrossRanks({*update->num, *update->den});
}

void ComputeLayerUpdateFromMappedPairs(const DisplayModel& model, BranchLayer which, const MappedPairs& pairs,
                                       const std::vector<float>& binned, const Patterns& t, LayerUpdate* update) {
  const size_t branch = which.branch;
  const int layer = which.layer;
  const size_t m = model.projection(layer).pixel_count() * 3;
  update->branch = branch, update->layer = layer;
  update->num->resize(m), update->den->resize(m);
  pairs.UpdateSums(layer, t[pairs.other_layer(layer)].rgb.data(), binned, update->num->data(), update->den->data());
  FinishOneTapSums(model.weight(branch), t[layer].rgb, update->num->data(), update->den->data());
  SumAcrossRanks({*update->num, *update->den});
}

}  // namespace layerlab
