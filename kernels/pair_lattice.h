// A branch of two one-tap layers a and b, its rays binned by the pixel pair
// they read. Every ray that reads pixel p_a of a and p_b of b adds the same
// terms to the multiplicative update's sums (kernels/one_tap_update.h),
//   num_a[p_a] += r t_b[p_b],   den_a[p_a] += t_b[p_b]^2,   and likewise for b,
// except for what the branch should emit along it, r. So the sums of either
// layer need only each pair's sum of r and its ray count: a solver that
// updates the branch several times toward the same r (the multiplicative
// solver's target, the hybrid's chase during a set's sub-iterations) bins r
// once and then sums a few pairs per pixel instead of every ray.
//
// Without rotation a ray's rows (row of a, row of b) depend on its view row
// and pixel row alone, its columns on its view column and pixel column, so
// the pairs are a dense lattice of row pairs x column pairs: cell (i, j)
// holds the rays of every view row and pixel row of row pair i and every
// view column and pixel column of column pair j, and its ray count is the
// product of theirs. The paper prototype's sets have 5.3 and 8.3 rays per
// cell on the dice (13 x 13 views of 400 x 200).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "layerlab/framework/huge_page_allocator.h"
#include "layerlab/framework/lightfield.h"
#include "layerlab/framework/rgb4.h"
#include "layerlab/systems/display_model.h"

namespace layerlab {

// A lattice's cells, [row pair][column pair][rgb, 0]: tens of MB streamed per
// update, in huge pages so that the prefetchers run on past 4 kB.
using PairCells = std::vector<Rgb4, HugePageAllocator<Rgb4>>;

class PairLattice {
 public:
  // Branch `branch` must suit (Suits).
  PairLattice(const DisplayModel& model, size_t branch);
  // Two layers, both read with one tap (one_tap_view.h).
  static bool Suits(const DisplayModel& model, size_t branch);
  // The lattice of a branch that suits and whose rays are at least twice
  // its cells (where binning once and summing cells is faster than summing
  // rays), or none.
  static std::optional<PairLattice> IfItPays(const DisplayModel& model, size_t branch);

  size_t cells() const { return row_pairs_.size() * col_pairs_.size(); }
  // The rays that read both layers (the others add nothing to either's sums).
  double rays() const { return rays_; }
  int layer_a() const { return layer_[0]; }
  int layer_b() const { return layer_[1]; }

  // binned[cell] = the sum of r over the cell's rays, r [view][row][col][rgb]
  // with the model's geometry; binned is resized to cells(). Each cell is
  // summed by one thread in a fixed order: the same bits for any thread count.
  void Bin(const LightField& r, PairCells* binned) const;

  // The sums of `layer` (a or b) from `binned` and the other layer's pattern
  // `other` as [pixel][rgb, 0] (PaddedLayers), as OneTapUpdateSums gives
  // them: num[p * 3 + c] = sum r q and den[p * 3 + c] = sum q^2 over the
  // rays that read pixel p, q the other layer's value along the ray (w_b
  // and the layer's own value left out). num and den hold the layer's
  // pixels x 3 and are written whole; each pixel row is summed by one
  // thread in a fixed order.
  void UpdateSums(int layer, const Rgb4* other, const PairCells& binned, double* num, double* den) const;
  int other_layer(int layer) const { return layer == layer_[0] ? layer_[1] : layer_[0]; }

 private:
  // A row (or column) of each layer, and how many (view row, pixel row)
  // pairs (or columns) of the light field read the two.
  struct AxisPair {
    int32_t own[2];
    int32_t rays;
  };
  // One side of the lattice: its layer's pixel rows in order, each with the
  // row pairs that read it.
  struct Side {
    std::vector<int32_t> first;      // [layer row]: its row pairs are order[first[r] .. first[r + 1])
    std::vector<int32_t> order;      // row pairs grouped by this side's layer row
    std::vector<int32_t> col_first;  // [layer column]: its column pairs are col_order[col_first[c] ..)
    std::vector<int32_t> col_order;  // column pairs grouped by this side's layer column
    std::vector<int32_t> other_col;  // [column pair]: the other layer's column
  };

  const LightFieldGeometry* geometry_;
  int layer_[2];
  int layer_cols_[2];
  std::vector<AxisPair> row_pairs_, col_pairs_;  // sorted by (a, b)
  std::vector<int32_t> col_pair_of_;             // [view col][pixel col]: its column pair, or -1
  std::vector<int32_t> col_source_first_;        // column pair j is read by (view col * cols + pixel col)
  std::vector<int32_t> col_sources_;             //   col_sources_[col_source_first_[j] ..), in that order
  std::vector<int32_t> source_first_,
      sources_;  // row pair i is read by (view row * rows + pixel row) sources_[source_first_[i] ..)
  Side side_[2];
  double rays_ = 0;
};

}  // namespace layerlab
