#include "layerlab/kernels/one_tap_view.h"

#include "layerlab/framework/error.h"
#include "layerlab/kernels/thread_merge.h"

namespace layerlab {

bool OneTapBranch(const DisplayModel& model, size_t b) {
  const std::vector<int>& layers = model.branch_layers(b);
  return !layers.empty() && layers.size() <= static_cast<size_t>(kMaxOneTapLayers) &&
         std::all_of(layers.begin(), layers.end(), [&](int k) { return model.projection(k).one_tap(); });
}

void PaddedLayers::Pad(const Patterns& t, const std::vector<int>& layers) {
  layers_.resize(t.size());
  for (int k : layers) PadRgb(t[k].rgb, &layers_[k]);
}

void PaddedLayers::PadAll(const Patterns& t) {
  layers_.resize(t.size());
  for (size_t k = 0; k < t.size(); ++k) PadRgb(t[k].rgb, &layers_[k]);
}

void PaddedLayers::PadRowsRead(const DisplayModel& model, const Patterns& t, const std::vector<int>& layers) {
  layers_.resize(t.size());
  const LightFieldGeometry& g = model.geometry();
  for (int k : layers) {
    const LayerProjection& P = model.projection(k);
    const RowSpan rows = RowsRead(P, g, 0, g.views_y);
    const std::vector<float>& rgb = t[k].rgb;
    std::vector<Rgb4>& out = layers_[k];
    out.resize(rgb.size() / 3);
    const size_t end = static_cast<size_t>(rows.end) * P.cols();
    for (size_t p = static_cast<size_t>(rows.begin) * P.cols(); p < end; ++p) out[p] = LoadRgb(&rgb[p * 3]);
  }
}

void PaddedLayers::Allocate(const std::vector<size_t>& pixels) {
  layers_.resize(pixels.size());
  for (size_t k = 0; k < pixels.size(); ++k) layers_[k].assign(pixels[k], Rgb4{});
}

size_t PaddedLayers::Bytes() const {
  size_t bytes = 0;
  for (const std::vector<Rgb4>& l : layers_) bytes += l.capacity() * sizeof(Rgb4);
  return bytes;
}

RowSpan RowsRead(const LayerProjection& P, const LightFieldGeometry& g, int vr_begin, int vr_end) {
  int lo = P.rows(), hi = 0;
  for (int vr = vr_begin; vr < vr_end; ++vr) {
    const AxisTap* row = P.row_taps(static_cast<size_t>(vr) * g.views_x);  // view row vr, column 0
    for (int i = 0; i < g.rows; ++i)
      if (const int32_t r = row[i].i0; r >= 0) lo = std::min(lo, r), hi = std::max(hi, r + 1);
  }
  return lo < hi ? RowSpan{lo, hi} : RowSpan{};
}

void ResampleToRayColumns(const LayerProjection& P, const Rgb4* pixels, int vc, int ray_cols, RowSpan rows,
                          std::vector<Rgb4>* out) {
  const AxisTap* col = P.col_taps(static_cast<size_t>(vc));  // view vc: row 0, column vc
  out->resize(static_cast<size_t>(P.rows()) * ray_cols);
  Rgb4* o = out->data();
  for (int r = rows.begin; r < rows.end; ++r)
    for (int j = 0; j < ray_cols; ++j)
      o[static_cast<size_t>(r) * ray_cols + j] =
          col[j].i0 < 0 ? Rgb4{} : pixels[static_cast<size_t>(r) * P.cols() + col[j].i0];
}

void ColumnSums::Reset(const LayerProjection& P, int ray_cols) {
  const size_t cells = static_cast<size_t>(P.rows()) * ray_cols;
  if (column_num_.size() != cells) {
    column_num_.assign(cells, Rgb4{});
    column_den_.assign(cells, Rgb4{});
  }
  ray_cols_ = ray_cols;
  touched_.assign(P.rows(), 0);
  // Only the rows some ray reads get sums (Scatter writes touched rows only):
  // on a strip of rays a few of the layer's rows. The others are never read.
  const LightFieldGeometry& g = P.geometry();
  reached_ = RowsRead(P, g, 0, g.views_y);
  layer_cols_ = P.cols();
  pixel_num_.resize(P.pixel_count()), pixel_den_.resize(P.pixel_count());
  const size_t begin = static_cast<size_t>(reached_.begin) * layer_cols_,
               end = static_cast<size_t>(reached_.end) * layer_cols_;
  std::fill(pixel_num_.begin() + begin, pixel_num_.begin() + end, Rgb4{});
  std::fill(pixel_den_.begin() + begin, pixel_den_.begin() + end, Rgb4{});
}

void ColumnSums::Allocate(int rows, int ray_cols, size_t pixels) {
  const size_t cells = static_cast<size_t>(rows) * ray_cols;
  column_num_.assign(cells, Rgb4{});
  column_den_.assign(cells, Rgb4{});
  touched_.assign(rows, 0);
  pixel_num_.assign(pixels, Rgb4{});
  pixel_den_.assign(pixels, Rgb4{});
  ray_cols_ = ray_cols;
}

size_t ColumnSums::BytesFor(int rows, int ray_cols, size_t pixels) {
  return (static_cast<size_t>(rows) * ray_cols * 2 + pixels * 2) * sizeof(Rgb4) + static_cast<size_t>(rows);
}

size_t ColumnSums::Bytes() const {
  return (column_num_.capacity() + column_den_.capacity() + pixel_num_.capacity() + pixel_den_.capacity()) *
             sizeof(Rgb4) +
         touched_.capacity();
}

void ColumnSums::Scatter(const LayerProjection& P, int vc) {
  const AxisTap* col = P.col_taps(static_cast<size_t>(vc));
  for (int r = 0; r < P.rows(); ++r) {
    if (!touched_[r]) continue;
    Rgb4* num = &column_num_[static_cast<size_t>(r) * ray_cols_];
    Rgb4* den = &column_den_[static_cast<size_t>(r) * ray_cols_];
    Rgb4* pixel_num = &pixel_num_[static_cast<size_t>(r) * P.cols()];
    Rgb4* pixel_den = &pixel_den_[static_cast<size_t>(r) * P.cols()];
    for (int j = 0; j < ray_cols_; ++j) {
      if (const int32_t c = col[j].i0; c >= 0) {
        pixel_num[c] += num[j];
        pixel_den[c] += den[j];
      }
      num[j] = den[j] = Rgb4{};
    }
    touched_[r] = 0;
  }
}

void ColumnSums::Merge(const std::vector<const ColumnSums*>& sums, int part, int parts, double* num, double* den) {
  // The rows no ray reads sum to 0 (as merged from cleared sums); the others merged.
  const ColumnSums& first = *sums.front();
  const size_t pixels = first.pixel_num_.size();
  const size_t begin = static_cast<size_t>(first.reached_.begin) * first.layer_cols_;
  const size_t end = static_cast<size_t>(first.reached_.end) * first.layer_cols_;
  auto zero = [&](size_t from, size_t to) {
    const size_t n = to - from, a = from + n * part / parts, b = from + n * (part + 1) / parts;
    std::fill(num + a * 3, num + b * 3, 0.0);
    std::fill(den + a * 3, den + b * 3, 0.0);
  };
  zero(0, begin), zero(end, pixels);
  std::vector<const float*> nums, dens;
  for (const ColumnSums* s : sums) {
    nums.push_back(reinterpret_cast<const float*>(s->pixel_num_.data() + begin));
    dens.push_back(reinterpret_cast<const float*>(s->pixel_den_.data() + begin));
  }
  MergeInThreadOrder(nums, end - begin, 4, part, parts, num + begin * 3);
  MergeInThreadOrder(dens, end - begin, 4, part, parts, den + begin * 3);
}

}  // namespace layerlab
