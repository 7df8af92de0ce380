#include "solvers/one_tap_update.h"

#include <omp.h>
#include <algorithm>
#include <cstdint>

#include "systems/one_tap_view.h"
#include "systems/row_kernels.h"

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

    for (int vr = vr_begin; vr < vr_end; ++vr) {
      const size_t view = g.view_index(vr, vc);
      const float* target = branch_target(view, w->target.data());
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
          AddBranchLightRow(q_rows, L - 1, Rgb4{1, 1, 1, 0}, cols, w->product.data());
          q = w->product.data();
        }
        if (view_errors)
          error += UpdateSumsAndErrorRow(l, q, own.data() + static_cast<size_t>(ra) * cols, weight,
                                         w->update_sums.num(ra), w->update_sums.den(ra), cols);
        else
          UpdateSumsRow(l, q, w->update_sums.num(ra), w->update_sums.den(ra), cols);
      }
      if (view_errors) view_errors[view] = error;
    }

    w->update_sums.Scatter(Pa, vc);
  }
};

}  // namespace

void OneTapUpdateSums(const DisplayModel& model, const std::vector<int>& layers, const Patterns& t,
                      const BranchTarget& branch_target, const std::array<float, 3>& weight, double* num, double* den,
                      double* view_errors, SolveWorkspace* workspace) {
  const LightFieldGeometry& g = model.geometry();
  const LayerProjection& Pa = model.projection(layers[0]);
  PaddedLayers& padded = workspace->padded;
  padded.PadRowsRead(model, t, view_errors ? layers : std::vector<int>(layers.begin() + 1, layers.end()));
  const Rgb4 w4{weight[0], weight[1], weight[2], 0.0f};

  // Each thread takes an equal run of views (ForEachViewRunOfThread), sums
  // them in float (a pixel gets a few rays per view), and the merge is in
  // double, in thread order: the same bits for a given thread count.
  std::vector<const ColumnSums*> thread_sums;
#pragma omp parallel
  {
    ThreadWorkspace& w = workspace->thread();
    w.update_sums.Reset(Pa, g.cols);
    w.target.resize(g.pixels_per_view() * 3);
    w.product.resize(g.cols);
    w.zeros.assign(g.cols, Rgb4{});
    const int threads = omp_get_num_threads(), me = omp_get_thread_num();
#pragma omp single
    thread_sums.resize(threads);
    thread_sums[me] = &w.update_sums;
    ForEachViewRunOfThread(g, me, threads, [&](int vc, int vr_begin, int vr_end) {
      ForLayerCount<Accumulate>(static_cast<int>(layers.size()), model, layers, padded, branch_target, w4, vc, vr_begin,
                                vr_end, view_errors, &w);
    });
#pragma omp barrier
    ColumnSums::Merge(thread_sums, me, threads, num, den);
  }
}

}  // namespace layerlab
