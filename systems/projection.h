// P_k: the map from a virtual layer's pixels to the light field's rays
// (paper Eq. 4-5), matrix-free.
//
// Ray (x, v) meets layer k at tan-angle u = p(z)/z = v D_k + (x - v) / z_lf
// as seen from the pupil center (finite at D_k = 0); the layer's sampling
// rule (layer_sampler.h) turns u into pixels. Without rotation the column
// depends only on (x_x, v_x) and the row only on (x_y, v_y): each view is two
// small tap tables. With rotation every ray is computed on the fly. Behind a
// real lens (VirtualLayer::ray_map) each channel's ray reads where the layer's
// ray map puts it, so its taps differ per channel (ForEachChannelTap). Nothing
// of light-field size is stored.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "layerlab/framework/lightfield.h"
#include "layerlab/systems/display_system.h"
#include "layerlab/systems/layer_sampler.h"

namespace layerlab {

class LayerProjection {
 public:
  LayerProjection(const VirtualLayer& layer, const LightFieldGeometry& lf, Sampling sampling);

  int cols() const { return sampler_.cols(); }
  int rows() const { return sampler_.rows(); }
  size_t pixel_count() const { return static_cast<size_t>(cols()) * rows(); }
  bool separable() const { return !map_ && sampler_.separable(); }
  // Behind a real lens: each channel's taps of a ray are its own.
  bool mapped() const { return map_ != nullptr; }
  // Bytes a mapped layer's tap table takes for a light field (0 otherwise): for memory estimates.
  static size_t MappedTableBytes(const VirtualLayer& layer, const LightFieldGeometry& lf, Sampling sampling);
  const SampledRayMap* ray_map() const { return map_.get(); }
  // A mapped layer with nearest sampling: view v's pixel per ray and channel,
  // [ray][rgb] (-1: misses); nullptr for any other layer.
  const int32_t* mapped_nearest(size_t view) const {
    return mapped_nearest_.empty() ? nullptr : &mapped_nearest_[view * lf_.pixels_per_view() * 3];
  }
  Sampling sampling() const { return sampler_.sampling(); }
  const LayerSampler& sampler() const { return sampler_; }
  const LightFieldGeometry& geometry() const { return lf_; }

  // Nearest sampling of an axis-aligned layer reads one pixel per ray, from
  // two tables per view: ray (i, j) reads pixel (row_taps(v)[i].i0,
  // col_taps(v)[j].i0), and misses the layer where either is -1.
  // Behind lenslets a ray's taps depend on its pupil point, not only on the offset the retina's one-tap
  // tables are keyed by: such a layer takes the general paths.
  bool one_tap() const { return separable() && sampling() == Sampling::kNearest && !sampler_.behind_lenslets(); }
  const AxisTap* row_taps(size_t view) const { return &row_taps_[(view / lf_.views_x) * lf_.rows]; }
  const AxisTap* col_taps(size_t view) const { return &col_taps_[(view % lf_.views_x) * lf_.cols]; }

  // The taps of ray (pixel row i, col j) of view v; a mapped layer's are per channel (ForEachChannelTap).
  RayTaps Taps(size_t view, int i, int j) const;

  // out[ray][c] = (P t)[ray][c] for the rays of one view; `pattern` is
  // [row][col][rgb] of this layer, `out` [row][col][rgb] of the view.
  void Gather(size_t view, const float* pattern, float* out) const;
  // out[ray][c] *= (P t)[ray][c]. A layer of several taps per ray needs a
  // view of samples first: `scratch` (resized to a view, [ray][rgb]), or a
  // buffer of its own without it.
  void GatherMultiply(size_t view, const float* pattern, float* out, std::vector<float>* scratch) const;
  void GatherMultiply(size_t view, const float* pattern, float* out) const;
  // accum[pixel][c] += (P^T values)[pixel][c] over the rays of one view.
  void ScatterAdd(size_t view, const float* values, double* accum) const;

  // 1 for each layer pixel some ray of the light field reads.
  std::vector<uint8_t> ReachedPixels() const;

  // Calls op(ray, pixel, weight) for every tap of the rays of one view that
  // reach the layer: the one loop that kernels fuse their work into.
  template <class Op>
  void ForEachTap(size_t view, Op op) const;
  // Calls op(ray, channel, pixel, weight) for every tap of every channel:
  // the loop for kernels that also run behind real lenses. Without a map it
  // is ForEachTap's order, channel innermost.
  template <class Op>
  void ForEachChannelTap(size_t view, Op op) const;

 private:
  LightFieldGeometry lf_;
  LayerSampler sampler_;
  // A ray's tan-angle on the layer is view_gain * v + pixel_gain * x (per axis).
  double view_gain_, pixel_gain_;  // D - 1/z_lf and 1/z_lf
  std::vector<AxisTap> col_taps_;  // [view col][pixel col], separable layers only
  std::vector<AxisTap> row_taps_;  // [view row][pixel row]
  std::shared_ptr<const SampledRayMap> map_;
  // A mapped layer with nearest sampling: every ray's pixel per channel,
  // [view][ray][channel] (-1: misses), made once (the general kernels read
  // each layer's taps several times per iteration). Bilinear taps are made per view.
  std::vector<int32_t> mapped_nearest_;

  // A mapped layer's taps of one view, [ray][channel]: with nearest sampling
  // a pixel (-1 where the ray misses or is lost), with bilinear its taps.
  struct MappedRays {
    std::vector<int32_t> nearest;
    std::vector<RayTaps> taps;
  };
  MappedRays MapView(size_t view) const;
};

template <class Op>
void LayerProjection::ForEachChannelTap(size_t view, Op op) const {
  if (!map_) {
    ForEachTap(view, [&](size_t ray, int32_t pixel, float weight) {
      for (int c = 0; c < 3; ++c) op(ray, c, pixel, weight);
    });
    return;
  }
  const size_t rays = lf_.pixels_per_view();
  if (sampling() == Sampling::kNearest) {
    const int32_t* pixels = &mapped_nearest_[view * rays * 3];
    for (size_t ray = 0; ray < rays; ++ray)
      for (int c = 0; c < 3; ++c)
        if (const int32_t pixel = pixels[ray * 3 + c]; pixel >= 0) op(ray, c, pixel, 1.0f);
    return;
  }
  const MappedRays mapped = MapView(view);
  for (size_t ray = 0; ray < rays; ++ray)
    for (int c = 0; c < 3; ++c) {
      const RayTaps& taps = mapped.taps[ray * 3 + c];
      for (int t = 0; t < taps.count; ++t) op(ray, c, taps.index[t], taps.weight[t]);
    }
}

template <class Op>
void LayerProjection::ForEachTap(size_t view, Op op) const {
  const int vr = static_cast<int>(view / lf_.views_x), vc = static_cast<int>(view % lf_.views_x);
  if (separable() && sampling() == Sampling::kNearest) {
    const AxisTap* col_tap = &col_taps_[static_cast<size_t>(vc) * lf_.cols];
    const AxisTap* row_tap = &row_taps_[static_cast<size_t>(vr) * lf_.rows];
    for (int i = 0; i < lf_.rows; ++i) {
      if (row_tap[i].i0 < 0) continue;
      const size_t ray_row = static_cast<size_t>(i) * lf_.cols;
      const int32_t pixel_row = row_tap[i].i0 * cols();
      for (int j = 0; j < lf_.cols; ++j)
        if (col_tap[j].i0 >= 0) op(ray_row + j, pixel_row + col_tap[j].i0, 1.0f);
    }
    return;
  }
  for (int i = 0; i < lf_.rows; ++i)
    for (int j = 0; j < lf_.cols; ++j) {
      RayTaps taps = Taps(view, i, j);
      for (int t = 0; t < taps.count; ++t) op(static_cast<size_t>(i) * lf_.cols + j, taps.index[t], taps.weight[t]);
    }
}

}  // namespace layerlab
