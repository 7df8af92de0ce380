// The normal matrix A^T A of an additive display, in layer space.
//
// A = sum_b w_b P_b (one layer per branch). When every layer is separable
// (no rotation), ray (view row v_r, view col v_c, pixel row i, col j) reads
// layer rows from (v_r, i) alone and layer columns from (v_c, j) alone, and
// the views form a full grid, so for each pair of layers
//   P_a^T P_b = R_ab (x) C_ab,  R_ab = sum_{v_r, i} r_a(v_r, i) r_b(v_r, i)^T,
//                               C_ab = sum_{v_c, j} c_a(v_c, j) c_b(v_c, j)^T
// (r, c the axis taps as vectors over the layer's rows and columns): a
// Kronecker product of two small banded matrices. A^T A x for layer a is
// then sum_b w_a w_b R_ab X_b C_ab^T per channel, X_b the layer image:
// microseconds of work where a pass over the rays takes tens of milliseconds.
#pragma once

#include <vector>

#include <Eigen/Sparse>

#include "layerlab/systems/display_model.h"

namespace layerlab {

// Per layer, [row][col][rgb].
using LayerVectors = std::vector<std::vector<double>>;

class AdditiveGram {
 public:
  // Every branch a single layer and every layer separable.
  static bool Applicable(const DisplayModel& model);
  explicit AdditiveGram(const DisplayModel& model);

  // out = A^T A x.
  void Apply(const LayerVectors& x, LayerVectors* out) const;

 private:
  struct Block {
    int a, b;                                                 // layers
    Eigen::SparseMatrix<double, Eigen::RowMajor> rows, cols;  // R_ab (rows_a x rows_b), C_ab (cols_a x cols_b)
    int first_row = 0, end_row = 0;                           // the rows of R_ab that hold a tap lie in [first, end)
  };
  const DisplayModel& model_;
  std::vector<Block> blocks_;
  std::vector<std::array<float, 3>> weight_;  // per layer: its branch's weight
};

}  // namespace layerlab
