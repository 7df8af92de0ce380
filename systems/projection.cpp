#include "layerlab/systems/projection.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "layerlab/systems/layer_ray_map.h"

namespace layerlab {

LayerProjection::LayerProjection(const VirtualLayer& layer, const LightFieldGeometry& lf, Sampling sampling)
    : lf_(lf),
      sampler_(layer, sampling),
      view_gain_(layer.diopters - 1.0 / lf.origin_z_m),
      pixel_gain_(1.0 / lf.origin_z_m),
      map_(layer.ray_map) {
  if (map_ && sampling == Sampling::kNearest) {
    const size_t per_view = lf.pixels_per_view() * 3;
    mapped_nearest_.resize(lf.view_count() * per_view);
#pragma omp parallel for schedule(dynamic)
    for (size_t v = 0; v < lf.view_count(); ++v) {
      const MappedRays rays = MapView(v);
      std::copy(rays.nearest.begin(), rays.nearest.end(), mapped_nearest_.begin() + v * per_view);
    }
  }
  if (!separable()) return;
  col_taps_.resize(static_cast<size_t>(lf.views_x) * lf.cols);
  for (int c = 0; c < lf.views_x; ++c)
    for (int j = 0; j < lf.cols; ++j)
      col_taps_[static_cast<size_t>(c) * lf.cols + j] =
          sampler_.Column(view_gain_ * lf.view_x(c) + pixel_gain_ * lf.pixel_x(j), lf.view_x(c));
  row_taps_.resize(static_cast<size_t>(lf.views_y) * lf.rows);
  for (int r = 0; r < lf.views_y; ++r)
    for (int i = 0; i < lf.rows; ++i)
      row_taps_[static_cast<size_t>(r) * lf.rows + i] =
          sampler_.Row(view_gain_ * lf.view_y(r) + pixel_gain_ * lf.pixel_y(i), lf.view_y(r));
}

LayerProjection::MappedRays LayerProjection::MapView(size_t view) const {
  const int vr = static_cast<int>(view / lf_.views_x), vc = static_cast<int>(view % lf_.views_x);
  const double p_x = lf_.view_x(vc), p_y = lf_.view_y(vr);
  const RayMapView map(*map_, p_x, p_y);
  std::vector<SampledRayMap::Cell> cols(lf_.cols), rows(lf_.rows);
  for (int j = 0; j < lf_.cols; ++j) cols[j] = map_->TanCell(0, (lf_.pixel_x(j) - p_x) * pixel_gain_);
  for (int i = 0; i < lf_.rows; ++i) rows[i] = map_->TanCell(1, (lf_.pixel_y(i) - p_y) * pixel_gain_);
  const size_t rays = lf_.pixels_per_view();
  const bool nearest = sampling() == Sampling::kNearest;
  MappedRays out;
  (nearest ? out.nearest.resize(rays * 3) : out.taps.resize(rays * 3));
  std::vector<double> U(rays * 2);
  for (int c = 0; c < 3; ++c) {
    map.Grid(c, cols, rows, U.data());
    for (size_t ray = 0; ray < rays; ++ray) {
      const double x = U[ray * 2], y = U[ray * 2 + 1];
      const RayTaps taps = std::isnan(x) || std::isnan(y) ? RayTaps{} : sampler_.At(x, y);
      if (nearest)
        out.nearest[ray * 3 + c] = taps.count ? taps.index[0] : -1;
      else
        out.taps[ray * 3 + c] = taps;
    }
  }
  return out;
}

size_t LayerProjection::MappedTableBytes(const VirtualLayer& layer, const LightFieldGeometry& lf, Sampling sampling) {
  return layer.ray_map && sampling == Sampling::kNearest ? lf.ray_count() * 3 * sizeof(int32_t) : 0;
}

RayTaps LayerProjection::Taps(size_t view, int i, int j) const {
  if (map_) throw std::logic_error("LayerProjection::Taps on a mapped layer: its taps are per channel");
  int vr = static_cast<int>(view / lf_.views_x), vc = static_cast<int>(view % lf_.views_x);
  if (separable())
    return LayerSampler::Combine(row_taps_[static_cast<size_t>(vr) * lf_.rows + i],
                                 col_taps_[static_cast<size_t>(vc) * lf_.cols + j], cols());
  return sampler_.At(view_gain_ * lf_.view_x(vc) + pixel_gain_ * lf_.pixel_x(j),
                     view_gain_ * lf_.view_y(vr) + pixel_gain_ * lf_.pixel_y(i), lf_.view_x(vc), lf_.view_y(vr));
}

void LayerProjection::Gather(size_t view, const float* pattern, float* out) const {
  std::fill(out, out + lf_.pixels_per_view() * 3, 0.0f);
  ForEachChannelTap(view, [&](size_t ray, int c, int32_t pixel, float w) {
    out[ray * 3 + c] += w * pattern[static_cast<size_t>(pixel) * 3 + c];
  });
}

void LayerProjection::GatherMultiply(size_t view, const float* pattern, float* out) const {
  std::vector<float> scratch;
  GatherMultiply(view, pattern, out, &scratch);
}

void LayerProjection::GatherMultiply(size_t view, const float* pattern, float* out, std::vector<float>* scratch) const {
  const int vr = static_cast<int>(view / lf_.views_x), vc = static_cast<int>(view % lf_.views_x);
  if (separable() && sampling() == Sampling::kNearest) {
    // One tap per ray: multiply in place; rays that miss the layer go dark.
    const AxisTap* col_tap = &col_taps_[static_cast<size_t>(vc) * lf_.cols];
    const AxisTap* row_tap = &row_taps_[static_cast<size_t>(vr) * lf_.rows];
    for (int i = 0; i < lf_.rows; ++i) {
      float* ray = out + static_cast<size_t>(i) * lf_.cols * 3;
      if (row_tap[i].i0 < 0) {
        std::fill(ray, ray + static_cast<size_t>(lf_.cols) * 3, 0.0f);
        continue;
      }
      const float* pixel_row = pattern + static_cast<size_t>(row_tap[i].i0) * cols() * 3;
      for (int j = 0; j < lf_.cols; ++j, ray += 3) {
        const int32_t col = col_tap[j].i0;
        if (col < 0) {
          ray[0] = ray[1] = ray[2] = 0.0f;
          continue;
        }
        const float* p = pixel_row + static_cast<size_t>(col) * 3;
        ray[0] *= p[0], ray[1] *= p[1], ray[2] *= p[2];
      }
    }
    return;
  }
  // Multiplying by a sum of taps needs the sum first.
  std::vector<float>& sampled = *scratch;
  sampled.resize(lf_.pixels_per_view() * 3);
  Gather(view, pattern, sampled.data());
  for (size_t k = 0; k < sampled.size(); ++k) out[k] *= sampled[k];
}

void LayerProjection::ScatterAdd(size_t view, const float* values, double* accum) const {
  ForEachChannelTap(view, [&](size_t ray, int c, int32_t pixel, float w) {
    accum[static_cast<size_t>(pixel) * 3 + c] += double(w) * values[ray * 3 + c];
  });
}

std::vector<uint8_t> LayerProjection::ReachedPixels() const {
  std::vector<uint8_t> reached(pixel_count(), 0);
#pragma omp parallel
  {
    std::vector<uint8_t> mine(pixel_count(), 0);
#pragma omp for schedule(dynamic)
    for (size_t v = 0; v < lf_.view_count(); ++v)
      ForEachChannelTap(v, [&](size_t, int, int32_t pixel, float) { mine[pixel] = 1; });
#pragma omp critical
    for (size_t p = 0; p < mine.size(); ++p) reached[p] |= mine[p];
  }
  return reached;
}

}  // namespace layerlab
