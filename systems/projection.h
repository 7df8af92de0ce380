// P_k: the map from a virtual layer's pixels to the light field's rays
// (paper Eq. 4-5), matrix-free.
//
// Ray (x, v) meets layer k at tan-angle u = p(z)/z = v D_k + (x - v) / z_lf
// as seen from the pupil center (finite at D_k = 0). With (a, b) = R(-rotation) (u - offset),
// the layer's grid coordinates (pixel centers at integers) are
//   col = cols/2 - 1/2 + a / tan_pitch_x,   row = rows/2 - 1/2 - b / tan_pitch_y
// (columns left to right, rows top to bottom in eye space), then mirrored
// for flip_x / flip_y into the panel's own order.
// Nearest sampling reads the pixel containing that point (the paper's binary
// P_k); bilinear blends the four around it. Rays that leave the grid read 0.
//
// Without rotation the column depends only on (x_x, v_x) and the row only on
// (x_y, v_y): each view is two small index tables. With rotation every ray
// is computed on the fly. Nothing of light-field size is stored.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "framework/lightfield.h"
#include "systems/display_system.h"

namespace layerlab {

enum class Sampling { kNearest, kBilinear };
std::string ToString(Sampling s);
Sampling SamplingFromString(const std::string& name);  // throws layerlab::Error

// Where one ray reads a layer: up to four pixels and their weights.
struct RayTaps {
  std::array<int32_t, 4> index{-1, -1, -1, -1};  // row * cols + col, -1 for none
  std::array<float, 4> weight{0, 0, 0, 0};
  int count = 0;
};

class LayerProjection {
 public:
  LayerProjection(const VirtualLayer& layer, const LightFieldGeometry& lf, Sampling sampling);

  int cols() const { return cols_; }
  int rows() const { return rows_; }
  size_t pixel_count() const { return static_cast<size_t>(cols_) * rows_; }
  bool separable() const { return separable_; }
  Sampling sampling() const { return sampling_; }
  const LightFieldGeometry& geometry() const { return lf_; }

  // The taps of ray (pixel row i, col j) of view v.
  RayTaps Taps(size_t view, int i, int j) const;

  // out[ray][c] = (P t)[ray][c] for the rays of one view; `pattern` is
  // [row][col][rgb] of this layer, `out` [row][col][rgb] of the view.
  void Gather(size_t view, const float* pattern, float* out) const;
  // out[ray][c] *= (P t)[ray][c].
  void GatherMultiply(size_t view, const float* pattern, float* out) const;
  // accum[pixel][c] += (P^T values)[pixel][c] over the rays of one view.
  void ScatterAdd(size_t view, const float* values, double* accum) const;

  // 1 for each layer pixel some ray of the light field reads.
  std::vector<uint8_t> ReachedPixels() const;

 private:
  struct AxisTap {
    int32_t i0 = -1, i1 = -1;  // -1: outside the grid
    float w0 = 0, w1 = 0;
  };
  AxisTap MakeAxisTap(double coordinate, int size, bool flip) const;
  template <class Op>
  void ForEachTap(size_t view, Op op) const;

  LightFieldGeometry lf_;
  Sampling sampling_;
  int cols_, rows_;
  bool separable_;
  // Layer-space affine map of a ray: u = a * v + b * x (per axis), from the ray equation.
  double view_gain_, pixel_gain_;  // D - 1/z_lf and 1/z_lf
  double offset_x_, offset_y_, cos_, sin_, tan_pitch_x_, tan_pitch_y_;
  bool flip_x_, flip_y_;
  std::vector<AxisTap> col_taps_;  // [view col][pixel col], separable layers only
  std::vector<AxisTap> row_taps_;  // [view row][pixel row]
};

}  // namespace layerlab
