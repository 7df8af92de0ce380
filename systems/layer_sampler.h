// Where a direction from the pupil reads a virtual layer: the one sampling
// rule shared by the light-field projections (P_k) and the retinal renderer.
//
// A point is given by its tan-angle u = (x/z, y/z) as seen from the pupil
// center on the layer's plane. With (a, b) = R(-rotation) (u - offset), the
// layer's grid coordinates (pixel centers at integers) are
//   col = cols/2 - 1/2 + a / tan_pitch_x,   row = rows/2 - 1/2 - b / tan_pitch_y
// (columns left to right and rows top to bottom in eye space), then mirrored
// for flip_x / flip_y into the panel's own order. Nearest sampling reads the
// pixel containing the point (the paper's binary P_k); bilinear blends the
// four around it. Points outside the grid read 0. Behind a lens array the
// point first moves by the lenslet the ray passes, which depends on the ray's
// pupil point p as well (lenslet_map.h): the overloads that take p.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>

#include "layerlab/systems/display_system.h"
#include "layerlab/systems/lenslet_map.h"

namespace layerlab {

enum class Sampling { kNearest, kBilinear };
std::string ToString(Sampling s);
Sampling SamplingFromString(const std::string& name);  // throws layerlab::Error

// One axis: up to two cells and their weights; -1 is outside the grid.
struct AxisTap {
  int32_t i0 = -1, i1 = -1;
  float w0 = 0, w1 = 0;
};

// Up to four pixels (row * cols + col) and their weights.
struct RayTaps {
  std::array<int32_t, 4> index{-1, -1, -1, -1};
  std::array<float, 4> weight{0, 0, 0, 0};
  int count = 0;
};

class LayerSampler {
 public:
  LayerSampler(const VirtualLayer& layer, Sampling sampling);

  int cols() const { return cols_; }
  int rows() const { return rows_; }
  double diopters() const { return diopters_; }
  Sampling sampling() const { return sampling_; }
  // Without rotation (and behind a square lattice of lenslets) a column depends only on u_x and a row only on u_y.
  bool separable() const { return separable_; }
  bool behind_lenslets() const { return lenslets_ != nullptr; }

  AxisTap Column(double tan_x) const;  // separable layers only
  AxisTap Row(double tan_y) const;     // separable layers only
  RayTaps At(double tan_x, double tan_y) const;
  // The same for a ray from pupil point p (m), for a layer behind lenslets.
  AxisTap Column(double tan_x, double pupil_x) const {
    return Column(lenslets_ ? lenslets_->ShiftX(pupil_x, tan_x) : tan_x);
  }
  AxisTap Row(double tan_y, double pupil_y) const { return Row(lenslets_ ? lenslets_->ShiftY(pupil_y, tan_y) : tan_y); }
  RayTaps At(double tan_x, double tan_y, double pupil_x, double pupil_y) const {
    if (!lenslets_) return At(tan_x, tan_y);
    const std::array<double, 2> u = lenslets_->Shift(pupil_x, pupil_y, tan_x, tan_y);
    return At(u[0], u[1]);
  }
  // The point's grid coordinates (col, row) in the panel's own order, pixel
  // centres at integers: the rule above before it picks cells.
  std::array<double, 2> PanelCoordinates(double tan_x, double tan_y) const;
  static RayTaps Combine(const AxisTap& row, const AxisTap& col, int cols);

 private:
  AxisTap Tap(double coordinate, int size, bool flip) const;

  Sampling sampling_;
  int cols_, rows_;
  bool separable_;
  double diopters_, eye_from_layer_tan_x_, eye_from_layer_tan_y_, cos_, sin_, tan_pitch_x_, tan_pitch_y_;
  bool flip_x_, flip_y_;
  std::shared_ptr<const LensletMap> lenslets_;
};

// Inline: the general and mapped projections call these once per ray and channel.
inline AxisTap LayerSampler::Tap(double coordinate, int size, bool flip) const {
  AxisTap tap;
  auto mirror = [&](int32_t index) { return flip ? size - 1 - index : index; };
  // floor() by truncation inside the grid (the same cells, without a libm call per ray); NaN lands outside.
  if (sampling_ == Sampling::kNearest) {
    const double shifted = coordinate + 0.5;
    if (shifted >= 0 && shifted < size) tap.i0 = mirror(static_cast<int32_t>(shifted)), tap.w0 = 1.0f;
    return tap;
  }
  if (!(coordinate >= -1 && coordinate < size)) return tap;
  const double low = coordinate >= 0 ? static_cast<double>(static_cast<int32_t>(coordinate)) : -1.0;
  double frac = coordinate - low;
  if (low >= 0 && low < size) tap.i0 = mirror(static_cast<int32_t>(low)), tap.w0 = static_cast<float>(1.0 - frac);
  if (low + 1 >= 0 && low + 1 < size) tap.i1 = mirror(static_cast<int32_t>(low + 1)), tap.w1 = static_cast<float>(frac);
  return tap;
}

inline AxisTap LayerSampler::Column(double tan_x) const {
  return Tap((tan_x - eye_from_layer_tan_x_) / tan_pitch_x_ + 0.5 * cols_ - 0.5, cols_, flip_x_);
}

inline AxisTap LayerSampler::Row(double tan_y) const {
  return Tap(-(tan_y - eye_from_layer_tan_y_) / tan_pitch_y_ + 0.5 * rows_ - 0.5, rows_, flip_y_);
}

inline RayTaps LayerSampler::Combine(const AxisTap& row, const AxisTap& col, int cols) {
  RayTaps taps;
  const int32_t ri[2] = {row.i0, row.i1}, ci[2] = {col.i0, col.i1};
  const float rw[2] = {row.w0, row.w1}, cw[2] = {col.w0, col.w1};
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b)
      if (ri[a] >= 0 && ci[b] >= 0 && rw[a] * cw[b] > 0) {
        taps.index[taps.count] = ri[a] * cols + ci[b];
        taps.weight[taps.count] = rw[a] * cw[b];
        ++taps.count;
      }
  return taps;
}

inline RayTaps LayerSampler::At(double tan_x, double tan_y) const {
  if (separable_) return Combine(Row(tan_y), Column(tan_x), cols_);
  double ux = tan_x - eye_from_layer_tan_x_, uy = tan_y - eye_from_layer_tan_y_;
  double a = cos_ * ux + sin_ * uy, b = -sin_ * ux + cos_ * uy;  // R(-rotation) u
  AxisTap col = Tap(a / tan_pitch_x_ + 0.5 * cols_ - 0.5, cols_, flip_x_);
  AxisTap row = Tap(-b / tan_pitch_y_ + 0.5 * rows_ - 0.5, rows_, flip_y_);
  return Combine(row, col, cols_);
}

}  // namespace layerlab
