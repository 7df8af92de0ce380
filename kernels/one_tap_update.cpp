#include "layerlab/kernels/one_tap_update.h"

#include <omp.h>
#include <algorithm>
#include <cstdint>
#include <vector>

#include "layerlab/framework/fixed_parts.h"
#include "layerlab/kernels/one_tap_view.h"
#include "layerlab/kernels/row_kernels.h"

namespace layerlab {
namespace {

// One thread's buffers (ThreadWorkspace): resampled[k], layer k at the
// rays' columns (layer a's too, for the error); update_sums, layer a's sums;
// target, one view of the branch target if it needs one; product, one ray
// row of the other layers' product; zeros, one ray row of no light.

// One view run's sums (and errors) for a branch of L layers.
template <int L>
struct Accumulate {
  static void Run(const DisplayModel& model, const std::vector<int>& layers, const PaddedLayers& padded,
                  const BranchTarget& branch_target, Rgb4 weight, int vc, int vr_begin, int vr_end, double* view_errors,
                  ThreadWorkspace* w) {
    const LightFieldGeometry& g = model.geometry();
    const int cols = g.cols;
    const LayerProjection& Pa = model.projection(layers[0]);

    for (int k = 1; k < L; ++k) {
      const LayerProjection& P = model.projection(layers[k]);
      ResampleToRayColumns(P, padded.pixels(layers[k]), vc, cols, RowsRead(P, g, vr_begin, vr_end),
                           &w->resampled[layers[k]]);
    }
    std::vector<Rgb4>& own = w->resampled[layers[0]];
    if (view_errors)
      ResampleToRayColumns(Pa, padded.pixels(layers[0]), vc, cols, RowsRead(Pa, g, vr_begin, vr_end), &own);

    // Without the errors and with at most one other layer, the ray rows wait
    // (stored targets only) and are summed grouped by the layer row they add
    // to: each layer row's column sums get the same adds in the same order
    // (view row, then ray row), kept in registers over a few ray rows, and
    // are read and written once per group instead of once per ray row.
    constexpr bool kGroupable = L <= 2;
    std::vector<PendingSumRow>& pending = w->pending_rows;
    auto flush = [&] {
      std::stable_sort(pending.begin(), pending.end(),
                       [](const PendingSumRow& x, const PendingSumRow& y) { return x.layer_row < y.layer_row; });
      constexpr size_t kBatch = 16;
      const float* r[kBatch];
      const Rgb4* q[kBatch];
      for (size_t b = 0, e = 0; b < pending.size(); b = e) {
        const int ra = pending[b].layer_row;
        for (e = b; e < pending.size() && pending[e].layer_row == ra;) ++e;
        for (size_t c = b; c < e; c += kBatch) {
          const size_t m = std::min(kBatch, e - c);
          for (size_t k = 0; k < m; ++k) r[k] = pending[c + k].target, q[k] = pending[c + k].product;
          UpdateSumsRows(r, L == 1 ? nullptr : q, static_cast<int>(m), {w->update_sums.num(ra), w->update_sums.den(ra)},
                         cols);
        }
      }
      pending.clear();
    };
    pending.clear();

    for (int vr = vr_begin; vr < vr_end; ++vr) {
      const size_t view = g.view_index(vr, vc);
      const float* target = branch_target(view, w->target.data());
      // A computed target lives until the next view's: this view's rows are summed now, after the earlier ones.
      const bool wait = kGroupable && !view_errors && target != w->target.data();
      if (kGroupable && !view_errors && !wait) flush();
      const AxisTap* row_taps[L];
      for (int k = 0; k < L; ++k) row_taps[k] = model.projection(layers[k]).row_taps(view);
      double error = 0;  // this view's, in row order
      // A ray that misses a layer gets no light from the branch: its error is r^2.
      auto unlit_row = [&](int i) {
        if (view_errors)
          error += SquaredErrorRow(target + static_cast<size_t>(i) * cols * 3, w->zeros.data(), cols, i == g.rows - 1);
      };
      for (int i = 0; i < g.rows; ++i) {
        const int32_t ra = row_taps[0][i].i0;
        if (ra < 0) {
          unlit_row(i);
          continue;
        }
        const Rgb4* q_rows[L > 1 ? L - 1 : 1] = {};
        bool reached = true;
        for (int k = 1; k < L && reached; ++k) {
          const int32_t r = row_taps[k][i].i0;
          reached = r >= 0;
          if (reached) q_rows[k - 1] = w->resampled[layers[k]].data() + static_cast<size_t>(r) * cols;
        }
        if (!reached) {
          unlit_row(i);
          continue;
        }
        const float* l = target + static_cast<size_t>(i) * cols * 3;
        const Rgb4* q = L == 1 ? nullptr : q_rows[0];
        if constexpr (L > 2) {  // the product of the other layers, then the sums
          std::fill(w->product.begin(), w->product.end(), Rgb4{});
          AddBranchLightRow({q_rows, L - 1, Rgb4{1, 1, 1, 0}, cols}, w->product.data());
          q = w->product.data();
        }
        if (view_errors)
          error += UpdateSumsAndErrorRow(l, q, own.data() + static_cast<size_t>(ra) * cols, weight,
                                         {w->update_sums.num(ra), w->update_sums.den(ra)}, cols);
        else if (wait)
          pending.push_back({ra, l, q});
        else
          UpdateSumsRow(l, q, {w->update_sums.num(ra), w->update_sums.den(ra)}, cols);
      }
      if (view_errors) view_errors[view] = error;
    }
    if (kGroupable) flush();

    w->update_sums.Scatter(Pa, vc);
  }
};

}  // namespace

void OneTapUpdateSums(const DisplayModel& model, const UpdatedBranch& branch, const Patterns& t,
                      const BranchTarget& branch_target, OneTapSums sums, SolveWorkspace* workspace) {
  const std::vector<int>& layers = branch.layers;
  const std::array<float, 3>& weight = branch.weight;
  double* view_errors = sums.view_errors;
  const LightFieldGeometry& g = model.geometry();
  const LayerProjection& Pa = model.projection(layers[0]);
  PaddedLayers& padded = workspace->padded;
  padded.PadRowsRead(model, t, view_errors ? layers : std::vector<int>(layers.begin() + 1, layers.end()));
  const Rgb4 w4{weight[0], weight[1], weight[2], 0.0f};

  // Each of the workspace's fixed parts takes an equal run of views
  // (ForEachViewRunOfThread), sums them in float (a pixel gets a few rays
  // per view), and the merge is in double, in part order: the same bits on
  // any team of at most that many threads (framework/fixed_parts.h).
  const int parts = workspace->threads();
  std::vector<const ColumnSums*> part_sums(parts);
#pragma omp parallel
  {
    ForEachPartOfThread(parts, [&](int p) {
      ThreadWorkspace& w = workspace->thread(p);
      w.update_sums.Reset(Pa, g.cols);
      w.target.resize(g.pixels_per_view() * 3);
      w.product.resize(g.cols);
      w.zeros.assign(g.cols, Rgb4{});
      part_sums[p] = &w.update_sums;
      ForEachViewRunOfThread(g, p, parts, [&](int vc, int vr_begin, int vr_end) {
        ForLayerCount<Accumulate>(static_cast<int>(layers.size()), model, layers, padded, branch_target, w4, vc,
                                  vr_begin, vr_end, view_errors, &w);
      });
    });
#pragma omp barrier
    ColumnSums::Merge(part_sums, omp_get_thread_num(), omp_get_num_threads(), sums.num, sums.den);
  }
}

}  // namespace layerlab
