#include "systems/projection.h"

#include <cmath>

#include "framework/error.h"

namespace layerlab {

std::string ToString(Sampling s) { return s == Sampling::kNearest ? "nearest" : "bilinear"; }

Sampling SamplingFromString(const std::string& name) {
  if (name == "nearest") return Sampling::kNearest;
  if (name == "bilinear") return Sampling::kBilinear;
  throw Error("unknown sampling \"" + name + "\"; expected nearest or bilinear");
}

LayerProjection::LayerProjection(const VirtualLayer& layer, const LightFieldGeometry& lf, Sampling sampling)
    : lf_(lf),
      sampling_(sampling),
      cols_(layer.cols),
      rows_(layer.rows),
      separable_(layer.rotation == 0.0),
      view_gain_(layer.diopters - 1.0 / lf.origin_z),
      pixel_gain_(1.0 / lf.origin_z),
      offset_x_(layer.offset_x),
      offset_y_(layer.offset_y),
      cos_(std::cos(layer.rotation)),
      sin_(std::sin(layer.rotation)),
      tan_pitch_x_(layer.tan_pitch_x),
      tan_pitch_y_(layer.tan_pitch_y),
      flip_x_(layer.flip_x),
      flip_y_(layer.flip_y) {
  if (!separable_) return;
  col_taps_.resize(static_cast<size_t>(lf.views_x) * lf.cols);
  for (int c = 0; c < lf.views_x; ++c)
    for (int j = 0; j < lf.cols; ++j) {
      double u = view_gain_ * lf.view_x(c) + pixel_gain_ * lf.pixel_x(j) - offset_x_;
      col_taps_[static_cast<size_t>(c) * lf.cols + j] = MakeAxisTap(u / tan_pitch_x_ + 0.5 * cols_ - 0.5, cols_, flip_x_);
    }
  row_taps_.resize(static_cast<size_t>(lf.views_y) * lf.rows);
  for (int r = 0; r < lf.views_y; ++r)
    for (int i = 0; i < lf.rows; ++i) {
      double u = view_gain_ * lf.view_y(r) + pixel_gain_ * lf.pixel_y(i) - offset_y_;
      // Rows count downward while y points up.
      row_taps_[static_cast<size_t>(r) * lf.rows + i] = MakeAxisTap(-u / tan_pitch_y_ + 0.5 * rows_ - 0.5, rows_, flip_y_);
    }
}

LayerProjection::AxisTap LayerProjection::MakeAxisTap(double coordinate, int size, bool flip) const {
  AxisTap tap;
  auto mirror = [&](int32_t index) { return flip ? size - 1 - index : index; };
  if (sampling_ == Sampling::kNearest) {
    double cell = std::floor(coordinate + 0.5);
    if (cell >= 0 && cell < size) tap.i0 = mirror(static_cast<int32_t>(cell)), tap.w0 = 1.0f;
    return tap;
  }
  double low = std::floor(coordinate);
  double frac = coordinate - low;
  if (low >= 0 && low < size) tap.i0 = mirror(static_cast<int32_t>(low)), tap.w0 = static_cast<float>(1.0 - frac);
  if (low + 1 >= 0 && low + 1 < size) tap.i1 = mirror(static_cast<int32_t>(low + 1)), tap.w1 = static_cast<float>(frac);
  return tap;
}

RayTaps LayerProjection::Taps(size_t view, int i, int j) const {
  int vr = static_cast<int>(view / lf_.views_x), vc = static_cast<int>(view % lf_.views_x);
  AxisTap col, row;
  if (separable_) {
    col = col_taps_[static_cast<size_t>(vc) * lf_.cols + j];
    row = row_taps_[static_cast<size_t>(vr) * lf_.rows + i];
  } else {
    double ux = view_gain_ * lf_.view_x(vc) + pixel_gain_ * lf_.pixel_x(j) - offset_x_;
    double uy = view_gain_ * lf_.view_y(vr) + pixel_gain_ * lf_.pixel_y(i) - offset_y_;
    double lx = cos_ * ux + sin_ * uy, ly = -sin_ * ux + cos_ * uy;  // R(-rotation) u
    col = MakeAxisTap(lx / tan_pitch_x_ + 0.5 * cols_ - 0.5, cols_, flip_x_);
    row = MakeAxisTap(-ly / tan_pitch_y_ + 0.5 * rows_ - 0.5, rows_, flip_y_);
  }
  RayTaps taps;
  const int32_t ri[2] = {row.i0, row.i1}, ci[2] = {col.i0, col.i1};
  const float rw[2] = {row.w0, row.w1}, cw[2] = {col.w0, col.w1};
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b)
      if (ri[a] >= 0 && ci[b] >= 0 && rw[a] * cw[b] > 0) {
        taps.index[taps.count] = ri[a] * cols_ + ci[b];
        taps.weight[taps.count] = rw[a] * cw[b];
        ++taps.count;
      }
  return taps;
}

template <class Op>
void LayerProjection::ForEachTap(size_t view, Op op) const {
  const int vr = static_cast<int>(view / lf_.views_x), vc = static_cast<int>(view % lf_.views_x);
  if (separable_ && sampling_ == Sampling::kNearest) {
    const AxisTap* cols = &col_taps_[static_cast<size_t>(vc) * lf_.cols];
    const AxisTap* rows = &row_taps_[static_cast<size_t>(vr) * lf_.rows];
    for (int i = 0; i < lf_.rows; ++i) {
      if (rows[i].i0 < 0) continue;
      const size_t ray_row = static_cast<size_t>(i) * lf_.cols;
      const int32_t pixel_row = rows[i].i0 * cols_;
      for (int j = 0; j < lf_.cols; ++j)
        if (cols[j].i0 >= 0) op(ray_row + j, pixel_row + cols[j].i0, 1.0f);
    }
    return;
  }
  for (int i = 0; i < lf_.rows; ++i)
    for (int j = 0; j < lf_.cols; ++j) {
      RayTaps taps = Taps(view, i, j);
      for (int t = 0; t < taps.count; ++t) op(static_cast<size_t>(i) * lf_.cols + j, taps.index[t], taps.weight[t]);
    }
}

void LayerProjection::Gather(size_t view, const float* pattern, float* out) const {
  std::fill(out, out + lf_.pixels_per_view() * 3, 0.0f);
  ForEachTap(view, [&](size_t ray, int32_t pixel, float w) {
    for (int c = 0; c < 3; ++c) out[ray * 3 + c] += w * pattern[static_cast<size_t>(pixel) * 3 + c];
  });
}

void LayerProjection::GatherMultiply(size_t view, const float* pattern, float* out) const {
  // Multiplying by a sum of taps needs the sum first; one view's buffer is small.
  std::vector<float> sampled(lf_.pixels_per_view() * 3);
  Gather(view, pattern, sampled.data());
  for (size_t k = 0; k < sampled.size(); ++k) out[k] *= sampled[k];
}

void LayerProjection::ScatterAdd(size_t view, const float* values, double* accum) const {
  ForEachTap(view, [&](size_t ray, int32_t pixel, float w) {
    for (int c = 0; c < 3; ++c) accum[static_cast<size_t>(pixel) * 3 + c] += double(w) * values[ray * 3 + c];
  });
}

std::vector<uint8_t> LayerProjection::ReachedPixels() const {
  std::vector<uint8_t> reached(pixel_count(), 0);
  for (size_t v = 0; v < lf_.view_count(); ++v) ForEachTap(v, [&](size_t, int32_t pixel, float) { reached[pixel] = 1; });
  return reached;
}

}  // namespace layerlab
