#include "solvers/joint_column_pass.h"

#include <omp.h>

#include <algorithm>
#include <cstdint>

#include "solvers/one_member_sums_row.h"
#include "systems/one_tap_view.h"
#include "systems/row_kernels.h"

namespace layerlab {
namespace {

// One thread's buffers (ThreadWorkspace): resampled[k], layer k at the
// rays' columns; layer_sums[k], its sums; light, one ray row of the whole display.
bool Summed(const std::vector<char>* summed, size_t k) { return !summed || (*summed)[k]; }

void Reset(const DisplayModel& model, const std::vector<char>* summed, ThreadWorkspace* w) {
  for (size_t k = 0; k < model.layer_count(); ++k)
    if (Summed(summed, k)) w->layer_sums[k].Reset(model.projection(k), model.geometry().cols);
  w->light.resize(model.geometry().cols);
}

// The sums over views [vr_begin, vr_end) of view column vc into w, and each
// view's ||l - l~||^2 into view_errors.
void ViewRun(const DisplayModel& model, const LightField& l, const PaddedLayers& padded, int vc, int vr_begin,
             int vr_end, const std::vector<char>* summed, double* view_errors, ThreadWorkspace* w) {
  const LightFieldGeometry& g = model.geometry();
  const int cols = g.cols;
  const size_t layers = model.layer_count();
  for (size_t k = 0; k < layers; ++k) {
    const LayerProjection& P = model.projection(k);
    ResampleToRayColumns(P, padded.pixels(static_cast<int>(k)), vc, cols, RowsRead(P, g, vr_begin, vr_end),
                         &w->resampled[k]);
  }

  std::vector<const Rgb4*> row(layers);  // each layer's resampled row for the current ray row, or null
  std::vector<int32_t> layer_row(layers);
  // A band of ray rows for every view of the run, then the next band: the
  // column sums the band reaches (eight arrays for four layers, 10 MB in
  // all at paper scale) stay in cache across the views, where view after
  // view would stream them all each time (pass 105 -> 80 ms).
  constexpr int kBandRows = 8;
  for (int vr = vr_begin; vr < vr_end; ++vr) view_errors[g.view_index(vr, vc)] = 0;
  for (int band = 0; band < g.rows; band += kBandRows)
    for (int vr = vr_begin; vr < vr_end; ++vr) {
      const size_t view = g.view_index(vr, vc);
      const float* target = l.view(view);
      double& error = view_errors[view];
      for (int i = band; i < std::min(g.rows, band + kBandRows); ++i) {
        for (size_t k = 0; k < layers; ++k) {
          layer_row[k] = model.projection(k).row_taps(view)[i].i0;
          row[k] = layer_row[k] < 0 ? nullptr : w->resampled[k].data() + static_cast<size_t>(layer_row[k]) * cols;
        }
        // The whole display's light in this ray row.
        Rgb4* light = w->light.data();
        std::fill(light, light + cols, Rgb4{});
        const Rgb4* rows[kMaxOneTapLayers];
        auto branch_rows = [&](size_t b) {
          const std::vector<int>& members = model.branch_layers(b);
          for (size_t m = 0; m < members.size(); ++m)
            if (!(rows[m] = row[members[m]])) return false;
          return true;
        };
        auto weight = [&](size_t b) {
          const std::array<float, 3>& wb = model.weight(b);
          return Rgb4{wb[0], wb[1], wb[2], 0.0f};
        };
        for (size_t b = 0; b < model.branch_count(); ++b) {
          if (!branch_rows(b)) continue;
          AddBranchLightRow(rows, static_cast<int>(model.branch_layers(b).size()), weight(b), cols, light);
        }
        const float* lr = target + static_cast<size_t>(i) * cols * 3;
        const bool exact_last = i == g.rows - 1;  // the view's last ray is read exactly
        error += SquaredErrorRow(lr, light, cols, exact_last);

        // Each layer's sums in the rays' columns.
        for (size_t b = 0; b < model.branch_count(); ++b) {
          if (!branch_rows(b)) continue;
          const std::vector<int>& members = model.branch_layers(b);
          if (summed) {  // the same sums, member by member
            for (size_t m = 0; m < members.size(); ++m)
              if (const int a = members[m]; (*summed)[a])
                OneMemberSumsRow(rows, static_cast<int>(members.size()), static_cast<int>(m), weight(b), cols, lr,
                                 exact_last, light, w->layer_sums[a].num(layer_row[a]),
                                 w->layer_sums[a].den(layer_row[a]));
            continue;
          }
          Rgb4* num[kMaxOneTapLayers];
          Rgb4* den[kMaxOneTapLayers];
          for (size_t m = 0; m < members.size(); ++m) {
            const int a = members[m];
            num[m] = w->layer_sums[a].num(layer_row[a]);
            den[m] = w->layer_sums[a].den(layer_row[a]);
          }
          JointSumsRow(rows, static_cast<int>(members.size()), weight(b), cols, lr, exact_last, light, num, den);
        }
      }
    }

  for (size_t k = 0; k < layers; ++k)
    if (Summed(summed, k)) w->layer_sums[k].Scatter(model.projection(k), vc);
}

}  // namespace

double JointColumnPass(const DisplayModel& model, const LightField& l, const Patterns& t,
                       std::vector<std::vector<double>>* num, std::vector<std::vector<double>>* den,
                       SolveWorkspace* workspace, const std::vector<char>* summed) {
  PaddedLayers& padded = workspace->padded;
  padded.PadAll(t);
  const LightFieldGeometry& g = model.geometry();
  std::vector<double> error(g.view_count());  // summed in view order: the same for any thread count
  std::vector<std::vector<const ColumnSums*>> thread_sums(model.layer_count());  // [layer][thread]
#pragma omp parallel
  {
    ThreadWorkspace& w = workspace->thread();
    Reset(model, summed, &w);
    const int threads = omp_get_num_threads(), me = omp_get_thread_num();
#pragma omp single
    for (auto& s : thread_sums) s.resize(threads);
    for (size_t k = 0; k < model.layer_count(); ++k) thread_sums[k][me] = &w.layer_sums[k];
    ForEachViewRunOfThread(g, me, threads, [&](int vc, int vr_begin, int vr_end) {
      ViewRun(model, l, padded, vc, vr_begin, vr_end, summed, error.data(), &w);
    });
#pragma omp barrier
    // Merged in thread order, each thread a share of each layer's pixels.
    for (size_t k = 0; k < model.layer_count(); ++k)
      if (Summed(summed, k)) ColumnSums::Merge(thread_sums[k], me, threads, (*num)[k].data(), (*den)[k].data());
  }
  double total = 0;
  for (double e : error) total += e;
  return total;
}

}  // namespace layerlab
