#include "layerlab/systems/source_spread.h"

#include <cmath>

#include "layerlab/framework/error.h"

namespace layerlab {
namespace {

// The spread along one axis in grid pixels of `pitch_m`: a Gaussian of FWHM `fwhm_m`, taps summing to `stride`.
DiffractionAxis SpreadAxis(double fwhm_m, double pitch_m, int stride) {
  const double sigma = fwhm_m / (2 * std::sqrt(2 * std::log(2.0))) / pitch_m;  // in pixels
  DiffractionAxis axis;
  axis.reach = static_cast<int>(std::ceil(kSpreadSigmas * sigma));
  axis.weight.resize(2 * axis.reach + 1);
  double sum = 0;
  for (int d = -axis.reach; d <= axis.reach; ++d)
    sum += axis.weight[d + axis.reach] = std::exp(-0.5 * d * d / (sigma * sigma));
  for (double& w : axis.weight) w *= stride / sum;
  return axis;
}

}  // namespace

bool IsSolvedEmitter(const VirtualLayer& layer) { return layer.panel.emitter && layer.panel.emitter->solved(); }

std::vector<LayerDiffraction> SourceSpread(const DisplaySystem& system) {
  std::vector<LayerDiffraction> out;
  for (size_t k = 0; k < system.layers.size(); ++k) {
    const VirtualLayer& layer = system.layers[k];
    if (!IsSolvedEmitter(layer)) continue;
    const EmitterSpec& e = *layer.panel.emitter;
    LayerDiffraction d{static_cast<int>(k), static_cast<int>(k), 0.0, {}};
    for (int c = 0; c < 3; ++c) {
      d.axes[c][0] = SpreadAxis(e.spread_fwhm_m, layer.panel.pitch_x_m, e.led_stride);
      d.axes[c][1] = SpreadAxis(e.spread_fwhm_m, layer.panel.pitch_y_m, e.led_stride);
    }
    out.push_back(std::move(d));
  }
  return out;
}

std::vector<LayerDiffraction> SeenKernels(const DisplaySystem& system, bool panel_diffraction) {
  std::vector<LayerDiffraction> kernels = SourceSpread(system);
  if (panel_diffraction)
    for (LayerDiffraction& d : PanelDiffraction(system)) kernels.push_back(std::move(d));
  return kernels;
}

LayerPattern LedValues(const VirtualLayer& layer, const LayerPattern& pattern) {
  if (!IsSolvedEmitter(layer) || pattern.cols != layer.cols || pattern.rows != layer.rows)
    throw Error("internal error: layer \"" + layer.name + "\" is not an LED array of this pattern's size");
  const EmitterSpec& e = *layer.panel.emitter;
  const int stride = e.led_stride, centre = stride / 2;
  LayerPattern leds(e.led_cols, e.led_rows, 0.0f);
  for (int i = 0; i < e.led_rows; ++i)
    for (int j = 0; j < e.led_cols; ++j)
      for (int c = 0; c < 3; ++c)
        leds.rgb[(size_t(i) * e.led_cols + j) * 3 + c] =
            pattern.rgb[(size_t(i * stride + centre) * layer.cols + j * stride + centre) * 3 + c];
  return leds;
}

void KeepEmitterSites(const VirtualLayer& layer, std::vector<float>* rgb) {
  if (!IsSolvedEmitter(layer)) return;
  const int stride = layer.panel.emitter->led_stride, centre = stride / 2;
  if (rgb->size() != size_t(layer.rows) * layer.cols * 3)
    throw Error("internal error: layer \"" + layer.name + "\"'s pattern is not its size");
  for (int i = 0; i < layer.rows; ++i)
    for (int j = 0; j < layer.cols; ++j)
      if (i % stride != centre || j % stride != centre)
        for (int c = 0; c < 3; ++c) (*rgb)[(size_t(i) * layer.cols + j) * 3 + c] = 0.0f;
}

}  // namespace layerlab
