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
      separable_(layer.rotation_rad == 0.0 && (!layer.lenslets || layer.lenslets->separable())),
      diopters_(layer.diopters),
      eye_from_layer_tan_x_(layer.eye_from_layer_tan_x),
      eye_from_layer_tan_y_(layer.eye_from_layer_tan_y),
      cos_(std::cos(layer.rotation_rad)),
      sin_(std::sin(layer.rotation_rad)),
      tan_pitch_x_(layer.tan_pitch_x),
      tan_pitch_y_(layer.tan_pitch_y),
      flip_x_(layer.flip_x),
      flip_y_(layer.flip_y),
      lenslets_(layer.lenslets) {}

std::array<double, 2> LayerSampler::PanelCoordinates(double tan_x, double tan_y) const {
  const double ux = tan_x - eye_from_layer_tan_x_, uy = tan_y - eye_from_layer_tan_y_;
  const double a = cos_ * ux + sin_ * uy, b = -sin_ * ux + cos_ * uy;  // R(-rotation) u
  const double col = a / tan_pitch_x_ + 0.5 * cols_ - 0.5, row = -b / tan_pitch_y_ + 0.5 * rows_ - 0.5;
  return {flip_x_ ? cols_ - 1 - col : col, flip_y_ ? rows_ - 1 - row : row};
}

}  // namespace layerlab
