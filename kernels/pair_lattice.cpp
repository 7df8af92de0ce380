#include "layerlab/kernels/pair_lattice.h"

#include <algorithm>
#include <numeric>
#include <tuple>

#include "layerlab/kernels/one_tap_view.h"
#include "layerlab/kernels/row_kernels.h"

namespace layerlab {
namespace {

// The distinct (tap of a, tap of b) pairs over `count` sources, sorted, and
// each source's pair (-1 where either tap misses).
template <class TapOf>
void PairsOf(int count, TapOf tap_of, std::vector<std::tuple<int32_t, int32_t, int32_t>>* pairs,
             std::vector<int32_t>* pair_of) {
  std::vector<std::tuple<int32_t, int32_t, int32_t>> keyed;  // (a, b, source)
  for (int s = 0; s < count; ++s) {
    const auto [a, b] = tap_of(s);
    if (a >= 0 && b >= 0) keyed.emplace_back(a, b, s);
  }
  std::sort(keyed.begin(), keyed.end());
  pair_of->assign(count, -1);
  pairs->clear();
  for (size_t k = 0; k < keyed.size(); ++k) {
    const auto [a, b, s] = keyed[k];
    if (k == 0 || std::get<0>(keyed[k - 1]) != a || std::get<1>(keyed[k - 1]) != b) pairs->emplace_back(a, b, 0);
    (*pair_of)[s] = static_cast<int32_t>(pairs->size() - 1);
    ++std::get<2>(pairs->back());
  }
}

// Members k = 0, 1, ... of groups group_of[k] (-1: none): group g's are
// members[first[g] .. first[g + 1]), in member order.
void GroupBy(const std::vector<int32_t>& group_of, size_t groups, std::vector<int32_t>* first,
             std::vector<int32_t>* members) {
  first->assign(groups + 1, 0);
  for (int32_t g : group_of)
    if (g >= 0) ++(*first)[g + 1];
  std::partial_sum(first->begin(), first->end(), first->begin());
  members->resize(first->back());
  std::vector<int32_t> next(first->begin(), first->end() - 1);
  for (size_t k = 0; k < group_of.size(); ++k)
    if (group_of[k] >= 0) (*members)[next[group_of[k]]++] = static_cast<int32_t>(k);
}

}  // namespace

bool PairLattice::Suits(const DisplayModel& model, size_t branch) {
  return model.branch_layers(branch).size() == 2 && OneTapBranch(model, branch);
}

std::optional<PairLattice> PairLattice::IfItPays(const DisplayModel& model, size_t branch) {
  if (!Suits(model, branch)) return std::nullopt;
  PairLattice lattice(model, branch);
  if (lattice.cells() == 0 || lattice.rays() < 2.0 * double(lattice.cells())) return std::nullopt;
  return lattice;
}

PairLattice::PairLattice(const DisplayModel& model, size_t branch) : geometry_(&model.geometry()) {
  const LightFieldGeometry& g = *geometry_;
  std::vector<int> layers = model.branch_layers(branch);
  std::sort(layers.begin(), layers.end());
  const LayerProjection* P[2] = {&model.projection(layers[0]), &model.projection(layers[1])};
  for (int s = 0; s < 2; ++s) layer_[s] = layers[s], layer_cols_[s] = P[s]->cols();

  std::vector<std::tuple<int32_t, int32_t, int32_t>> pairs;
  std::vector<int32_t> row_pair_of;  // [view row * rows + pixel row]
  PairsOf(
      g.views_y * g.rows,
      [&](int s) {
        const size_t view = g.view_index(s / g.rows, 0);
        return std::pair{P[0]->row_taps(view)[s % g.rows].i0, P[1]->row_taps(view)[s % g.rows].i0};
      },
      &pairs, &row_pair_of);
  for (const auto& [a, b, n] : pairs) row_pairs_.push_back({{a, b}, n});
  PairsOf(
      g.views_x * g.cols,
      [&](int s) {
        const size_t view = g.view_index(0, s / g.cols);
        return std::pair{P[0]->col_taps(view)[s % g.cols].i0, P[1]->col_taps(view)[s % g.cols].i0};
      },
      &pairs, &col_pair_of_);
  for (const auto& [a, b, n] : pairs) col_pairs_.push_back({{a, b}, n});

  GroupBy(row_pair_of, row_pairs_.size(), &source_first_, &sources_);
  GroupBy(col_pair_of_, col_pairs_.size(), &col_source_first_, &col_sources_);

  double row_rays = 0, col_rays = 0;
  for (const AxisPair& p : row_pairs_) row_rays += p.rays;
  for (const AxisPair& p : col_pairs_) col_rays += p.rays;
  rays_ = row_rays * col_rays;

  for (int s = 0; s < 2; ++s) {
    Side& side = side_[s];
    std::vector<int32_t> row_of, col_of;
    for (const AxisPair& p : row_pairs_) row_of.push_back(p.own[s]);
    for (const AxisPair& p : col_pairs_) col_of.push_back(p.own[s]), side.other_col.push_back(p.own[1 - s]);
    GroupBy(row_of, P[s]->rows(), &side.first, &side.order);
    GroupBy(col_of, P[s]->cols(), &side.col_first, &side.col_order);
  }
}

void PairLattice::Bin(const LightField& r, PairCells* binned) const {
  const LightFieldGeometry& g = *geometry_;
  const size_t row_floats = static_cast<size_t>(g.cols) * 3;
  const size_t width = col_pairs_.size();
  binned->resize(cells());
  Rgb4* out = binned->data();
#pragma omp parallel
  {
    // The row pair's rays, its sources' rows summed, [view col][pixel col][rgb]
    // (and room for LoadRgbOver at the end); each cell then gathers its columns.
    std::vector<float> summed(g.views_x * row_floats + 1);
#pragma omp for schedule(static)
    for (size_t i = 0; i < row_pairs_.size(); ++i) {
      const int32_t* source = &sources_[source_first_[i]];
      const int32_t count = source_first_[i + 1] - source_first_[i];
      auto ray_row = [&](int32_t k, int vc) {
        return r.view(g.view_index(source[k] / g.rows, vc)) + static_cast<size_t>(source[k] % g.rows) * row_floats;
      };
      for (int vc = 0; vc < g.views_x; ++vc) {
        // The rows are a few kB each, scattered over the views: the next view column's are fetched meanwhile.
        if (vc + 1 < g.views_x)
          for (int32_t k = 0; k < count; ++k) {
            const char* next = reinterpret_cast<const char*>(ray_row(k, vc + 1));
            for (size_t b = 0; b < row_floats * sizeof(float); b += 64) __builtin_prefetch(next + b);
          }
        float* sum = &summed[vc * row_floats];
        const float* first = ray_row(0, vc);
        std::copy(first, first + row_floats, sum);
        for (int32_t k = 1; k < count; ++k) {
          const float* row = ray_row(k, vc);
          for (size_t f = 0; f < row_floats; ++f) sum[f] += row[f];
        }
      }
      Rgb4* cell = out + i * width;
      for (size_t j = 0; j < width; ++j) {
        Rgb4 total{};
        for (int32_t k = col_source_first_[j]; k < col_source_first_[j + 1]; ++k)
          total += LoadRgbOver(&summed[3 * static_cast<size_t>(col_sources_[k])]);
        cell[j] = total;
      }
    }
  }
}

void PairLattice::UpdateSums(int layer, const Rgb4* other, const PairCells& binned, double* num, double* den) const {
  const int s = layer == layer_[0] ? 0 : 1, o = 1 - s;
  const Side& side = side_[s];
  const size_t other_cols = static_cast<size_t>(layer_cols_[o]);
  const int own_cols = layer_cols_[s];
  const size_t own_row = static_cast<size_t>(own_cols) * 3;
  const int rows = static_cast<int>(side.first.size()) - 1;
  const size_t width = col_pairs_.size();
  const int32_t* other_col = side.other_col.data();
#pragma omp parallel
  {
    // This layer row's sums over its row pairs, per column pair; lane 3 unused.
    std::vector<Rgb4> sum_rq(width), sum_qq(width);
    std::vector<const Rgb4*> cells, q_rows;  // of the row's row pairs
    std::vector<float> row_rays;
// Rows hold from none to a dozen row pairs: handed out a few at a time.
#pragma omp for schedule(dynamic, 4)
    for (int r = 0; r < rows; ++r) {
      double* num_row = num + static_cast<size_t>(r) * own_row;
      double* den_row = den + static_cast<size_t>(r) * own_row;
      if (side.first[r] == side.first[r + 1]) {
        std::fill(num_row, num_row + own_row, 0.0);
        std::fill(den_row, den_row + own_row, 0.0);
        continue;
      }
      cells.clear(), q_rows.clear(), row_rays.clear();
      for (int32_t k = side.first[r]; k < side.first[r + 1]; ++k) {
        const int32_t i = side.order[k];
        cells.push_back(binned.data() + static_cast<size_t>(i) * width);
        q_rows.push_back(other + static_cast<size_t>(row_pairs_[i].own[o]) * other_cols);
        row_rays.push_back(static_cast<float>(row_pairs_[i].rays));
      }
      PairSumsRows({cells.data(), q_rows.data(), row_rays.data(), static_cast<int>(cells.size())},
                   {other_col, static_cast<int>(width)}, {sum_rq.data(), sum_qq.data()});
      // A pixel's column pairs, each of its count of rays per row pair.
      for (int c = 0; c < own_cols; ++c) {
        double n[3] = {0, 0, 0}, d[3] = {0, 0, 0};
        for (int32_t k = side.col_first[c]; k < side.col_first[c + 1]; ++k) {
          const int32_t j = side.col_order[k];
          const double rays = col_pairs_[j].rays;
          for (int ch = 0; ch < 3; ++ch) n[ch] += sum_rq[j][ch], d[ch] += rays * sum_qq[j][ch];
        }
        for (int ch = 0; ch < 3; ++ch) num_row[3 * c + ch] = n[ch], den_row[3 * c + ch] = d[ch];
      }
    }
  }
}

}  // namespace layerlab
