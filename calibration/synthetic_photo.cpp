#include "layerlab/calibration/synthetic_photo.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "layerlab/calibration/synthetic_measurements.h"
#include "layerlab/framework/error.h"
#include "layerlab/systems/layer_ray_map.h"

namespace layerlab {
namespace {

// One panel as shown: its transmittance per pixel of the full grid.
struct ShownPanel {
  const VirtualLayer* layer = nullptr;
  std::vector<float> transmittance;
  // Ray (origin o, slope t) -> panel pixel is affine through ideal optics: base + o_x dx[0] + o_y dx[1] + t_x dx[2] + t_y dx[3],
  // its coefficients read off PanelPixelAt(PanelPointOfRay(...)) once.
  std::array<double, 2> base;
  std::array<std::array<double, 2>, 4> dx;

  void Linearize() {
    auto pixel = [&](double ox, double oy, double tx, double ty) {
      return PanelPixelAt(*layer, PanelPointOfRay(*layer, {ox, oy}, {tx, ty}));
    };
    base = pixel(0, 0, 0, 0);
    const double h = 1e-3;  // exact for an affine map; small keeps the rounding small
    const std::array<std::array<double, 2>, 4> ends = {pixel(h, 0, 0, 0), pixel(0, h, 0, 0), pixel(0, 0, h, 0),
                                                       pixel(0, 0, 0, h)};
    for (int i = 0; i < 4; ++i) dx[i] = {(ends[i][0] - base[0]) / h, (ends[i][1] - base[1]) / h};
  }
  std::array<double, 2> PixelOfRay(const std::array<double, 2>& o, const std::array<double, 2>& t) const {
    if (layer->ray_map) {
      // Behind a real lens: the traced ray (green, for a gray camera) on the layer's paraxial grid, U = X / b.
      const auto u = layer->ray_map->Lookup(1, o[0], o[1], t[0], t[1]);
      if (!u) return {NAN, NAN};
      const double b = std::abs(layer->transfer.b);
      return PanelPixelAt(*layer, {b * (*u)[0], b * (*u)[1]});
    }
    return {base[0] + o[0] * dx[0][0] + o[1] * dx[1][0] + t[0] * dx[2][0] + t[1] * dx[3][0],
            base[1] + o[0] * dx[0][1] + o[1] * dx[1][1] + t[0] * dx[2][1] + t[1] * dx[3][1]};
  }

  float at(double col, double row) const {
    const PanelSpec& p = layer->panel;
    const double c = std::floor(col + 0.5), r = std::floor(row + 0.5);
    if (!(c >= 0 && r >= 0 && c < static_cast<double>(p.resolution_cols) && r < static_cast<double>(p.resolution_rows)))
      return 0.0f;
    return transmittance[static_cast<size_t>(r) * static_cast<size_t>(p.resolution_cols) + static_cast<size_t>(c)];
  }
};

double Mean(const Rgb& rgb) { return (rgb[0] + rgb[1] + rgb[2]) / 3.0; }

// Every panel's transmittance as shown; a panel the capture does not name shows white.
std::vector<ShownPanel> ShownPanels(const DisplaySystem& truth, const CapturePlan& plan,
                                    const PlannedCapture& capture) {
  std::vector<ShownPanel> panels(truth.layers.size());
  for (size_t i = 0; i < truth.layers.size(); ++i) {
    const VirtualLayer& layer = truth.layers[i];
    std::string name = layer.name + "_white.png";
    for (const auto& [panel, file] : capture.show)
      if (panel == layer.name) name = file.substr(file.find_last_of('/') + 1);
    const std::vector<uint8_t> codes = PatternImage(truth, plan, layer.name, name);
    const PanelSpec& p = layer.panel;
    panels[i].layer = &layer;
    panels[i].Linearize();
    panels[i].transmittance.resize(codes.size());
    for (size_t k = 0; k < codes.size(); ++k) {
      const double x = codes[k] / 255.0;
      panels[i].transmittance[k] =
          static_cast<float>(Mean(p.max_transmittance) * (p.black_level + (1 - p.black_level) * std::pow(x, p.gamma)));
    }
  }
  return panels;
}

}  // namespace

PhotoRenderer::PhotoRenderer(const PhotoCamera& camera) : camera_(camera) {
  CheckPhotoCamera(camera);
  slopes_ = PixelCornerSlopes(camera);
}

Image PhotoRenderer::Render(const DisplaySystem& truth, const CapturePlan& plan, const PlannedCapture& capture,
                            uint64_t seed_key) const {
  RefuseTiltedPanels(truth, "a synthetic photograph");
  const std::vector<ShownPanel> panels = ShownPanels(truth, plan, capture);
  // The base exposure puts the brightest branch's full white at camera.white.
  std::vector<double> branch_scale(truth.branches.size());
  double brightest = 0;
  for (size_t b = 0; b < truth.branches.size(); ++b) {
    branch_scale[b] = truth.branches[b].backlight_luminance_cd_m2 * Mean(truth.branches[b].optics_efficiency);
    double white = branch_scale[b];
    for (int l : truth.branches[b].layers) white *= Mean(truth.layers[l].panel.max_transmittance);
    brightest = std::max(brightest, white);
  }
  if (!(brightest > 0)) throw Error(truth.file + ": the display shows no light (no backlight or an opaque path)");
  const double gain = camera_.white * capture.exposure / brightest;

  // The light of every branch along one ray from the camera's aperture.
  auto light = [&](const std::array<double, 2>& aperture_point, const std::array<double, 2>& slope) {
    const std::array<double, 2> origin = {capture.camera_position[0] + aperture_point[0],
                                          capture.camera_position[1] + aperture_point[1]};
    double sum = 0;
    for (size_t b = 0; b < truth.branches.size(); ++b) {
      double branch = branch_scale[b];
      for (int l : truth.branches[b].layers) {
        const ShownPanel& panel = panels[l];
        const auto pixel_at = panel.PixelOfRay(origin, slope);
        branch *= panel.at(pixel_at[0], pixel_at[1]);
        if (branch == 0) break;
      }
      sum += branch;
    }
    return gain * sum;
  };
  return RecordOnSensor(camera_, PixelSignals(camera_, slopes_, seed_key, light), seed_key);
}

}  // namespace layerlab
