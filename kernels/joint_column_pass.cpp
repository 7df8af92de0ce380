#include "layerlab/kernels/joint_column_pass.h"

#include <omp.h>

#include <algorithm>
#include <cstdint>
#include <optional>

#include "layerlab/framework/error.h"
#include "layerlab/framework/fixed_parts.h"
#include "layerlab/kernels/depth_sums_row.h"
#include "layerlab/kernels/one_tap_view.h"
#include "layerlab/kernels/row_kernels.h"

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

void PrefetchRow(const float* p, int floats) {
  const char* c = reinterpret_cast<const char*>(p);
  for (size_t o = 0; o < floats * sizeof(float); o += 64) __builtin_prefetch(c + o, 0, 3);
}

Rgb4 Weight(const DisplayModel& model, size_t b) {
  const std::array<float, 3>& wb = model.weight(b);
  return Rgb4{wb[0], wb[1], wb[2], 0.0f};
}

bool EqualLayerCounts(const DisplayModel& model) {
  for (size_t b = 1; b < model.branch_count(); ++b)
    if (model.branch_layers(b).size() != model.branch_layers(0).size()) return false;
  return true;
}

// The fused pass's arguments to DepthSumsRow (branches of equal layer
// counts): with `summed`, each branch's summed member, else every member;
// and for each ray row the branches its rays reach.
class FusedRows {
 public:
  FusedRows(const DisplayModel& model, const std::vector<char>* summed) : model_(model), summed_(summed) {
    layers_ = static_cast<int>(model.branch_layers(0).size());
    if (!EqualLayerCounts(model)) throw Error("a one-depth pass needs branches of equal layer counts");
    for (size_t b = 0; b < model.branch_count() && summed; ++b) {
      const std::vector<int>& members = model.branch_layers(b);
      int a = -1;
      for (size_t m = 0; m < members.size(); ++m)
        if ((*summed)[members[m]]) {
          if (a >= 0) throw Error("a one-depth pass sums one layer of each branch");
          a = static_cast<int>(m);
        }
      if (a < 0) throw Error("a one-depth pass sums one layer of each branch");
      member_of_.push_back(a);
    }
    const size_t branches = model.branch_count(), sums = summed ? branches : branches * layers_;
    rows_.resize(branches * layers_), member_.resize(branches), weight_.resize(branches);
    res_.resize(sums), den_.resize(sums);
  }

  bool summed(size_t layer) const { return Summed(summed_, layer); }

  // The ray row whose layer rows are row[k] (null: missed) at layer rows layer_row[k]; then DepthSumsRow.
  void Sums(const std::vector<const Rgb4*>& row, const std::vector<int32_t>& layer_row, const float* l, bool exact_last,
            int cols, double* squared_error, std::vector<ColumnSums>* sums) {
    int reached = 0;
    for (size_t b = 0; b < model_.branch_count(); ++b) {
      const std::vector<int>& members = model_.branch_layers(b);
      bool all = true;
      for (int m = 0; m < layers_ && all; ++m) all = (rows_[reached * layers_ + m] = row[members[m]]) != nullptr;
      if (!all) continue;
      weight_[reached] = Weight(model_, b);
      if (summed_) {
        const int a = members[member_of_[b]];
        member_[reached] = member_of_[b];
        res_[reached] = (*sums)[a].num(layer_row[a]);
        den_[reached] = (*sums)[a].den(layer_row[a]);
      } else {
        for (int m = 0; m < layers_; ++m) {
          const int a = members[m];
          res_[reached * layers_ + m] = (*sums)[a].num(layer_row[a]);
          den_[reached * layers_ + m] = (*sums)[a].den(layer_row[a]);
        }
      }
      ++reached;
    }
    DepthSumsRow({rows_.data(), layers_, layers_, weight_.data(), reached}, cols, summed_ ? member_.data() : nullptr,
                 {l, exact_last}, squared_error, {res_.data(), den_.data()});
  }

 private:
  const DisplayModel& model_;
  const std::vector<char>* summed_;
  int layers_ = 0;
  std::vector<int> member_of_;  // [branch], with summed_
  // The reached branches' arguments.
  std::vector<const Rgb4*> rows_;
  std::vector<int> member_;
  std::vector<Rgb4> weight_;
  std::vector<Rgb4*> res_, den_;
};

// The sums over views [vr_begin, vr_end) of view column vc into w, and each
// view's ||l - l~||^2 into view_errors if `objective`.
void ViewRun(const DisplayModel& model, const LightField& l, const PaddedLayers& padded, int vc, int vr_begin,
             int vr_end, FusedRows* fused, bool objective, double* view_errors, ThreadWorkspace* w) {
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
        const float* lr = target + static_cast<size_t>(i) * cols * 3;
        const bool exact_last = i == g.rows - 1;  // the view's last ray is read exactly
        if (fused) {
          // The target's next ray row in this order on its way while this
          // one is summed: the band order jumps between views, and the
          // hardware prefetcher starts each new stream late (the rank-2 pass
          // 0.9x the time).
          if (i + 1 < std::min(g.rows, band + kBandRows))
            PrefetchRow(lr + cols * 3, cols * 3);
          else if (vr + 1 < vr_end)
            PrefetchRow(l.view(g.view_index(vr + 1, vc)) + static_cast<size_t>(band) * cols * 3, cols * 3);
          else if (band + kBandRows < g.rows)
            PrefetchRow(l.view(g.view_index(vr_begin, vc)) + static_cast<size_t>(band + kBandRows) * cols * 3,
                        cols * 3);
          double row_error = 0;
          fused->Sums(row, layer_row, lr, exact_last, cols, objective ? &row_error : nullptr, &w->layer_sums);
          error += row_error;
          continue;
        }

        Rgb4* light = w->light.data();  // the whole display's light in this ray row
        std::fill(light, light + cols, Rgb4{});
        const Rgb4* rows[kMaxOneTapLayers];
        auto branch_rows = [&](size_t b) {
          const std::vector<int>& members = model.branch_layers(b);
          for (size_t m = 0; m < members.size(); ++m)
            if (!(rows[m] = row[members[m]])) return false;
          return true;
        };
        for (size_t b = 0; b < model.branch_count(); ++b) {
          if (!branch_rows(b)) continue;
          AddBranchLightRow({rows, static_cast<int>(model.branch_layers(b).size()), Weight(model, b), cols}, light);
        }
        error += SquaredErrorRow(lr, light, cols, exact_last);

        // Each layer's sums in the rays' columns.
        for (size_t b = 0; b < model.branch_count(); ++b) {
          if (!branch_rows(b)) continue;
          const std::vector<int>& members = model.branch_layers(b);
          Rgb4* res[kMaxOneTapLayers];
          Rgb4* den[kMaxOneTapLayers];
          for (size_t m = 0; m < members.size(); ++m) {
            const int a = members[m];
            res[m] = w->layer_sums[a].num(layer_row[a]);
            den[m] = w->layer_sums[a].den(layer_row[a]);
          }
          JointSumsRow({rows, static_cast<int>(members.size()), Weight(model, b), cols}, {lr, exact_last}, light,
                       {res, den});
        }
      }
    }

  for (size_t k = 0; k < layers; ++k)
    if (!fused || fused->summed(k)) w->layer_sums[k].Scatter(model.projection(k), vc);
}

}  // namespace

double JointColumnPass(const DisplayModel& model, const LightField& l, const Patterns& t, JointLayerSums sums,
                       SolveWorkspace* workspace, const std::vector<char>* summed, bool objective) {
  PaddedLayers& padded = workspace->padded;
  padded.PadAll(t);
  const LightFieldGeometry& g = model.geometry();
  std::vector<double> error(g.view_count());  // summed in view order: the same for any thread count
  std::vector<std::vector<const ColumnSums*>> part_sums(model.layer_count());  // [layer][part]
  // Checked here, copied by each thread; branches of unequal layer counts take the general path.
  std::optional<FusedRows> each_fused;
  if (summed || EqualLayerCounts(model)) each_fused.emplace(model, summed);
  // Views cut into the workspace's fixed parts, merged in part order (framework/fixed_parts.h).
  const int parts = workspace->threads();
  for (auto& s : part_sums) s.resize(parts);
#pragma omp parallel
  {
    ForEachPartOfThread(parts, [&](int p) {
      ThreadWorkspace& w = workspace->thread(p);
      Reset(model, summed, &w);
      for (size_t k = 0; k < model.layer_count(); ++k) part_sums[k][p] = &w.layer_sums[k];
      std::optional<FusedRows> fused = each_fused;
      ForEachViewRunOfThread(g, p, parts, [&](int vc, int vr_begin, int vr_end) {
        ViewRun(model, l, padded, vc, vr_begin, vr_end, fused ? &*fused : nullptr, objective, error.data(), &w);
      });
    });
#pragma omp barrier
    // Merged in part order, each thread a share of each layer's pixels.
    const int threads = omp_get_num_threads(), me = omp_get_thread_num();
    for (size_t k = 0; k < model.layer_count(); ++k)
      if (Summed(summed, k)) ColumnSums::Merge(part_sums[k], me, threads, (*sums.res)[k].data(), (*sums.den)[k].data());
  }
  double total = 0;
  for (double e : error) total += e;
  return total;
}

}  // namespace layerlab
