#include "layerlab/systems/layer_sampler.h"

#include <cmath>

#include "layerlab/framework/error.h"

namespace layerlab {

std::string ToString(Sampling s) { return s == Sampling::kNearest ? "nearest" : "bilinear"; }

Sampling SamplingFromString(const std::string& name) {
  if (name == "nearest") return Sampling::kNearest;
  if (name == "bilinear") return Sampling::kBilinear;
  throw Error("unknown sampling \"" + name + "\"; expected nearest or bilinear");
}

LayerSampler::LayerSampler(const VirtualLayer& layer, Sampling sampling)
    : sampling_(sampling),
      cols_(layer.cols),
      rows_(layer.rows),
      separable_(layer.rotation_rad == 0.0),
      diopters_(layer.diopters),
      eye_from_layer_tan_x_(layer.eye_from_layer_tan_x),
      eye_from_layer_tan_y_(layer.eye_from_layer_tan_y),
      cos_(std::cos(layer.rotation_rad)),
      sin_(std::sin(layer.rotation_rad)),
      tan_pitch_x_(layer.tan_pitch_x),
      tan_pitch_y_(layer.tan_pitch_y),
      flip_x_(layer.flip_x),
      flip_y_(layer.flip_y) {}

AxisTap LayerSampler::Tap(double coordinate, int size, bool flip) const {
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

AxisTap LayerSampler::Column(double tan_x) const {
  return Tap((tan_x - eye_from_layer_tan_x_) / tan_pitch_x_ + 0.5 * cols_ - 0.5, cols_, flip_x_);
}

AxisTap LayerSampler::Row(double tan_y) const {
  return Tap(-(tan_y - eye_from_layer_tan_y_) / tan_pitch_y_ + 0.5 * rows_ - 0.5, rows_, flip_y_);
}

RayTaps LayerSampler::Combine(const AxisTap& row, const AxisTap& col, int cols) {
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

RayTaps LayerSampler::At(double tan_x, double tan_y) const {
  if (separable_) return Combine(Row(tan_y), Column(tan_x), cols_);
  double ux = tan_x - eye_from_layer_tan_x_, uy = tan_y - eye_from_layer_tan_y_;
  double a = cos_ * ux + sin_ * uy, b = -sin_ * ux + cos_ * uy;  // R(-rotation) u
  AxisTap col = Tap(a / tan_pitch_x_ + 0.5 * cols_ - 0.5, cols_, flip_x_);
  AxisTap row = Tap(-b / tan_pitch_y_ + 0.5 * rows_ - 0.5, rows_, flip_y_);
  return Combine(row, col, cols_);
}

}  // namespace layerlab
