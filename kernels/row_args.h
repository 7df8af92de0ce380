// The arguments the row kernels (row_kernels.h, depth_sums_row.h) share,
// grouped by what they are: small structs of pointers and counts, passed by
// value and unpacked at each kernel's top, so the loops are those of the
// unpacked arguments.
#pragma once

#include <cstdint>

#include "layerlab/framework/rgb4.h"

namespace layerlab {

// One ray row of a branch: rows[k][j] for its layers k < layers (1 to 4) and
// the row's rays j < cols, weighted by w.
struct BranchRow {
  const Rgb4* const* rows;
  int layers;
  Rgb4 w;
  int cols;
};

// One ray row of several branches (or terms) of `layers` layers each:
// branch b's layer k is rows[b * stride + k] (stride >= layers), weighted by
// w[b], b < branches.
struct BranchRows {
  const Rgb4* const* rows;
  int stride;
  int layers;
  const Rgb4* w;
  int branches;
};

// A row of rays packed [ray][rgb]. Every ray but the last may be read as
// four floats (one past its own); the last too unless `exact_last`.
struct PackedRow {
  const float* values;
  bool exact_last;
};

// Two sums per column of a layer row: the multiplicative update's
// num (r q) and den (q^2).
struct UpdateRowSums {
  Rgb4* num;
  Rgb4* den;
};

// The joint pass's two sums per column for each member a of a branch:
// res[a][j] and den[a][j].
struct MemberRowSums {
  Rgb4* const* res;
  Rgb4* const* den;
};

// `pairs` row pairs of a pixel-pair lattice (pair_lattice.h) for one layer
// row: pair k has the binned target cells[k], the other layer's pixel row
// q_rows[k] and rays[k] rays per cell.
struct PairRows {
  const Rgb4* const* cells;
  const Rgb4* const* q_rows;
  const float* rays;
  int pairs;
};

// The column pairs of a lattice row: column pair j reads the other layer's
// pixel q_col[j], j < width.
struct PairColumns {
  const int32_t* q_col;
  int width;
};

}  // namespace layerlab
