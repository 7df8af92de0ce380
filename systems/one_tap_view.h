// The fast path of the common case: every layer of a branch read with nearest
// sampling and no rotation (LayerProjection::one_tap). In one view the column a
// layer reads then depends on the ray's column only and its row on the ray's
// row only, so the rays of a view that reach every layer of the branch are
// listed once (OneTapView::columns), and each ray row is one pass over that
// list with every layer's pattern row fixed. Patterns are read padded to
// [pixel][rgb, 0] (PaddedLayers) so that a pixel is one vector load.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <variant>
#include <vector>

#include "framework/rgb4.h"
#include "systems/display_model.h"

namespace layerlab {

// Branches of up to this many layers take the fast path.
constexpr int kMaxOneTapLayers = 4;

// True if branch b takes the fast path.
bool OneTapBranch(const DisplayModel& model, size_t b);

// Each layer's pattern as [pixel][rgb, 0]; only the layers asked for are filled.
class PaddedLayers {
 public:
  void Pad(const Patterns& t, const std::vector<int>& layers);
  void PadAll(const Patterns& t);
  const Rgb4* pixels(int layer) const { return layers_[layer].data(); }

 private:
  std::vector<std::vector<Rgb4>> layers_;
};

template <int L>
class OneTapView {
 public:
  struct Column {
    int32_t ray;       // column in the view
    int32_t pixel[L];  // column read in each layer
  };

  // Rays on a grid of ray_rows x ray_cols (a light-field view, or the retina
  // for one pupil point): ray column j reads column col_taps[k][j].i0 of layer
  // layers[k] and ray row i its row row_taps[k][i].i0 (-1: misses it).
  OneTapView(const DisplayModel& model, const int* layers, const AxisTap* const* row_taps,
             const AxisTap* const* col_taps, int ray_rows, int ray_cols)
      : ray_rows_(ray_rows), ray_cols_(ray_cols) {
    for (int k = 0; k < L; ++k) {
      layers_[k] = layers[k];
      row_taps_[k] = row_taps[k];
      cols_[k] = model.projection(layers[k]).cols();
    }
    columns_.reserve(ray_cols);
    for (int j = 0; j < ray_cols; ++j) {
      Column c{j, {}};
      bool reached = true;
      for (int k = 0; k < L; ++k) reached = reached && (c.pixel[k] = col_taps[k][j].i0) >= 0;
      if (reached) columns_.push_back(c);
    }
  }

  // The rays of light-field view `view`; `layers`: L layer indices.
  OneTapView(const DisplayModel& model, const int* layers, size_t view)
      : OneTapView(model, layers, Taps(model, layers, view, true).data(), Taps(model, layers, view, false).data(),
                   model.geometry().rows, model.geometry().cols) {}

  // The columns of the rays that reach every layer, left to right.
  const std::vector<Column>& columns() const { return columns_; }

  // rows[k] = the pattern row of layer k that ray row i reads; false if some layer misses it.
  bool Rows(const PaddedLayers& padded, int i, const Rgb4* rows[L]) const {
    for (int k = 0; k < L; ++k) {
      const int32_t r = row_taps_[k][i].i0;
      if (r < 0) return false;
      rows[k] = padded.pixels(layers_[k]) + static_cast<size_t>(r) * cols_[k];
    }
    return true;
  }

  // How many of the listed columns of ray row i may read one float past their
  // ray (into the next ray's red) in a [row][col][rgb] buffer of this grid:
  // all but the grid's very last ray.
  size_t OverreadSafe(int i) const {
    const bool last = i == ray_rows_ - 1 && !columns_.empty() && columns_.back().ray == ray_cols_ - 1;
    return columns_.size() - (last ? 1 : 0);
  }

 private:
  static std::array<const AxisTap*, L> Taps(const DisplayModel& model, const int* layers, size_t view, bool rows) {
    std::array<const AxisTap*, L> taps;
    for (int k = 0; k < L; ++k)
      taps[k] = rows ? model.projection(layers[k]).row_taps(view) : model.projection(layers[k]).col_taps(view);
    return taps;
  }

  int ray_rows_, ray_cols_;
  int layers_[L];
  const AxisTap* row_taps_[L];
  int cols_[L];
  std::vector<Column> columns_;
};

// One view of a fast-path branch, whatever its number of layers.
class OneTapBranchView {
 public:
  // Light-field view `view`.
  OneTapBranchView(const DisplayModel& model, size_t b, size_t view);
  // Any grid of rays (OneTapView); the tables are per layer of the branch, in its order.
  OneTapBranchView(const DisplayModel& model, size_t b, const AxisTap* const* row_taps, const AxisTap* const* col_taps,
                   int ray_rows, int ray_cols);
  // row[j] += the light of the branch in ray (i, j) of the view, w_b prod_k P_k t_k.
  void AddRow(const PaddedLayers& padded, int i, Rgb4* row) const;

 private:
  std::variant<OneTapView<1>, OneTapView<2>, OneTapView<3>, OneTapView<4>> view_;
  Rgb4 weight_;
};

// One ray row [ray][rgb, 0] into [ray][rgb], writing exactly cols x 3 floats.
void PackRow(const Rgb4* row, int cols, float* out);

}  // namespace layerlab
