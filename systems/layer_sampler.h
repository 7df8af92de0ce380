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
// four around it. Points outside the grid read 0.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "layerlab/systems/display_system.h"

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
  // Without rotation a column depends only on u_x and a row only on u_y.
  bool separable() const { return separable_; }

  AxisTap Column(double tan_x) const;  // separable layers only
  AxisTap Row(double tan_y) const;     // separable layers only
  RayTaps At(double tan_x, double tan_y) const;
  static RayTaps Combine(const AxisTap& row, const AxisTap& col, int cols);

 private:
  AxisTap Tap(double coordinate, int size, bool flip) const;

  Sampling sampling_;
  int cols_, rows_;
  bool separable_;
  double diopters_, eye_from_layer_tan_x_, eye_from_layer_tan_y_, cos_, sin_, tan_pitch_x_, tan_pitch_y_;
  bool flip_x_, flip_y_;
};

}  // namespace layerlab
