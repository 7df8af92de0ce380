// The fast path of the common case: every layer of a branch read with nearest
// sampling and no rotation (LayerProjection::one_tap). In one view the column a
// layer reads then depends on the ray's column only and its row on the ray's
// row only, so the rays of a view that reach every layer of the branch are
// listed once (OneTapView::columns), and each ray row is one pass over that
// list with every layer's pattern row fixed. Patterns are read padded to
// [pixel][rgb, 0] (PaddedLayers) so that a pixel is one vector load.
#pragma once

#include <algorithm>
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

  // `layers`: L layer indices (of one branch, in any order).
  OneTapView(const DisplayModel& model, const int* layers, size_t view) : model_(&model) {
    for (int k = 0; k < L; ++k) {
      const LayerProjection& p = model.projection(layers[k]);
      layers_[k] = layers[k];
      row_taps_[k] = p.row_taps(view);
      cols_[k] = p.cols();
    }
    columns_.reserve(model.geometry().cols);
    for (int j = 0; j < model.geometry().cols; ++j) {
      Column c{j, {}};
      bool reached = true;
      for (int k = 0; k < L; ++k) reached = reached && (c.pixel[k] = model.projection(layers[k]).col_taps(view)[j].i0) >= 0;
      if (reached) columns_.push_back(c);
    }
  }

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
  // ray (into the next ray's red): all but the view's very last ray.
  size_t OverreadSafe(int i) const {
    const std::vector<Column>& c = columns_;
    const bool last = i == model_->geometry().rows - 1 && !c.empty() && c.back().ray == model_->geometry().cols - 1;
    return c.size() - (last ? 1 : 0);
  }

 private:
  const DisplayModel* model_;
  int layers_[L];
  const AxisTap* row_taps_[L];
  int cols_[L];
  std::vector<Column> columns_;
};

// One view of a fast-path branch, whatever its number of layers.
class OneTapBranchView {
 public:
  OneTapBranchView(const DisplayModel& model, size_t b, size_t view);
  // row[j] += the light of the branch in ray (i, j) of the view, w_b prod_k P_k t_k.
  void AddRow(const PaddedLayers& padded, int i, Rgb4* row) const;

 private:
  std::variant<OneTapView<1>, OneTapView<2>, OneTapView<3>, OneTapView<4>> view_;
  Rgb4 weight_;
};

// One ray row [ray][rgb, 0] into [ray][rgb]; `last` says if it ends its buffer.
void PackRow(const Rgb4* row, int cols, bool last, float* out);

}  // namespace layerlab
