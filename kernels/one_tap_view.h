// The fast path of the common case: every layer of a branch read with nearest
// sampling and no rotation (LayerProjection::one_tap), at most
// kMaxOneTapLayers per branch. Patterns are read padded to [pixel][rgb, 0]
// (PaddedLayers) so that a pixel is one vector load.
//
// The light-field passes run view column by view column, each layer resampled
// once to the rays' columns (view_synthesizer.h, kernels/one_tap_update.h,
// kernels/joint_column_pass.h); the retina resamples each layer row once per
// column table (retina.cpp).
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "layerlab/framework/rgb4.h"
#include "layerlab/kernels/row_kernels.h"
#include "layerlab/kernels/unrolled_layers.h"
#include "layerlab/systems/display_model.h"

namespace layerlab {

// True if branch b takes the fast path.
bool OneTapBranch(const DisplayModel& model, size_t b);

// Each layer's pattern as [pixel][rgb, 0]; only the layers asked for are filled.
class PaddedLayers {
 public:
  void Pad(const Patterns& t, const std::vector<int>& layers);
  void PadAll(const Patterns& t);
  // The same, of each layer only the rows some ray of the model's light field
  // reads (RowsRead; on a strip a few): room for all, the others left as they
  // were and never read by the passes that resample through RowsRead.
  void PadRowsRead(const DisplayModel& model, const Patterns& t, const std::vector<int>& layers);
  const Rgb4* pixels(int layer) const { return layers_[layer].data(); }
  // Room for `pixels[k]` pixels of layer k, touched (solve_workspace.h sizes it); the bytes held.
  void Allocate(const std::vector<size_t>& pixels);
  size_t Bytes() const;

 private:
  std::vector<std::vector<Rgb4>> layers_;
};

// Layer rows [begin, end): the rows of a layer some rays read.
struct RowSpan {
  int begin = 0, end = 0;
};

// The rows of layer P that the rays of view rows [vr_begin, vr_end) read
// (a view's row taps depend on its view row alone); empty if none.
RowSpan RowsRead(const LayerProjection& P, const LightFieldGeometry& g, int vr_begin, int vr_end);

// Layer P's padded pattern at the rays' columns of view column vc,
// [its row][ray column], 0 where a ray misses the layer: within a view
// column a layer's column tap depends on the ray's column alone. Only the
// layer rows in `rows` are written (a strip of rays reads a few); out has
// room for all of them, the others are left as they were and must not be read.
void ResampleToRayColumns(const LayerProjection& P, const Rgb4* pixels, int vc, int ray_cols, RowSpan rows,
                          std::vector<Rgb4>* out);

// Thread `me` of `threads`' equal share of the views in view-column order,
// as runs within one view column: f(vc, vr_begin, vr_end) for each. Whole
// view columns per thread would leave one thread idle for a column in
// thirteen; only the columns a run boundary cuts are resampled twice.
template <class F>
void ForEachViewRunOfThread(const LightFieldGeometry& g, int me, int threads, F f) {
  const int64_t views = int64_t(g.views_x) * g.views_y;
  const int64_t end = views * (me + 1) / threads;
  for (int64_t k = views * me / threads; k < end;) {
    const int vc = static_cast<int>(k / g.views_y), vr_begin = static_cast<int>(k % g.views_y);
    const int vr_end = static_cast<int>(std::min<int64_t>(g.views_y, vr_begin + (end - k)));
    f(vc, vr_begin, vr_end);
    k += vr_end - vr_begin;
  }
}

// One layer's multiplicative-update sums (numerator and denominator) for one
// thread: summed in the rays' columns over the ray rows of a view column,
// then scattered to the layer's pixels once per view column.
class ColumnSums {
 public:
  // For a pass: the pixel sums zeroed, of the layer rows some ray reads (the
  // column sums are always clear between view columns).
  void Reset(const LayerProjection& P, int ray_cols);
  // The column sums of layer row r, marked as holding sums.
  Rgb4* num(int r) {
    touched_[r] = 1;
    return &column_num_[static_cast<size_t>(r) * ray_cols_];
  }
  Rgb4* den(int r) {
    touched_[r] = 1;
    return &column_den_[static_cast<size_t>(r) * ray_cols_];
  }
  // The column sums into the pixel sums through view column vc's column taps; clears them.
  void Scatter(const LayerProjection& P, int vc);
  // num[pixel * 3 + c] = the sum of `sums`' pixel sums in their order, and
  // den likewise (merging threads, in double; kernels/thread_merge.h), for
  // share `part` of `parts` of the pixels: each thread of a team merges its own share.
  static void Merge(const std::vector<const ColumnSums*>& sums, int part, int parts, double* num, double* den);

  // Room for the sums of any layer of at most `rows` rows and `pixels`
  // pixels, touched, so that Reset never allocates (solve_workspace.h sizes
  // it); what that takes, and what is held.
  void Allocate(int rows, int ray_cols, size_t pixels);
  static size_t BytesFor(int rows, int ray_cols, size_t pixels);
  size_t Bytes() const;

 private:
  int ray_cols_ = 0;
  std::vector<Rgb4> column_num_, column_den_;  // [layer row][ray column]
  std::vector<uint8_t> touched_;               // layer rows that hold column sums
  std::vector<Rgb4> pixel_num_, pixel_den_;    // [pixel], held for the rows in reached_ only
  RowSpan reached_;                            // the layer rows some ray of the light field reads
  int layer_cols_ = 0;
};

}  // namespace layerlab
