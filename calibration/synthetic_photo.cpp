#include "layerlab/calibration/synthetic_photo.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "layerlab/calibration/synthetic_measurements.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/random.h"
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

// Separable Gaussian blur, the border extended.
void Blur(std::vector<double>& image, int width, int height, double sigma) {
  if (!(sigma > 0)) return;
  const int radius = static_cast<int>(std::ceil(3.5 * sigma));
  std::vector<double> kernel(2 * radius + 1);
  double total = 0;
  for (int i = -radius; i <= radius; ++i) total += kernel[i + radius] = std::exp(-0.5 * i * i / (sigma * sigma));
  for (double& k : kernel) k /= total;
  std::vector<double> out(image.size());
  for (int pass = 0; pass < 2; ++pass) {
    const int n = pass == 0 ? width : height;
    for (int r = 0; r < height; ++r)
      for (int c = 0; c < width; ++c) {
        double sum = 0;
        for (int i = -radius; i <= radius; ++i) {
          const int at = std::clamp((pass == 0 ? c : r) + i, 0, n - 1);
          sum += kernel[i + radius] *
                 image[pass == 0 ? static_cast<size_t>(r) * width + at : static_cast<size_t>(at) * width + c];
        }
        out[static_cast<size_t>(r) * width + c] = sum;
      }
    image.swap(out);
  }
}

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

// Each pixel's signal before blur and noise, `gain` times the mean over its
// samples of the light of every branch. Stratified samples jittered anew in
// every photograph: on a fixed grid an edge's rendered place would lock to the
// grid's steps (1/s pixel), a bias no blur afterwards removes.
std::vector<double> PixelSignals(const PhotoCamera& camera, const std::vector<double>& slopes,
                                 const DisplaySystem& truth, const PlannedCapture& capture,
                                 const std::vector<ShownPanel>& panels, const std::vector<double>& branch_scale,
                                 double gain, uint64_t seed_key) {
  const int s = camera.supersampling, samples = s * s;
  const double radius = 0.5 * camera.aperture_m;
  std::vector<double> signals(static_cast<size_t>(camera.width) * camera.height);
  SplitMix64 jitter(MixSeed(camera.seed, seed_key ^ 0x5a3b1e0d7c9f2468ull));
  const size_t row = static_cast<size_t>(camera.width) + 1;
  for (size_t pixel = 0; pixel < signals.size(); ++pixel) {
    const size_t u = pixel % static_cast<size_t>(camera.width), v = pixel / static_cast<size_t>(camera.width);
    const double* c00 = &slopes[(v * row + u) * 2];
    const double* c10 = c00 + 2;
    const double* c01 = c00 + row * 2;
    const double* c11 = c01 + 2;
    if (std::isnan(c00[0]) || std::isnan(c10[0]) || std::isnan(c01[0]) || std::isnan(c11[0])) continue;
    double sum = 0;
    for (int k = 0; k < samples; ++k) {
      const double fx = (k % s + jitter.uniform()) / s, fy = (k / s + jitter.uniform()) / s;
      const double t[2] = {(1 - fy) * ((1 - fx) * c00[0] + fx * c10[0]) + fy * ((1 - fx) * c01[0] + fx * c11[0]),
                           (1 - fy) * ((1 - fx) * c00[1] + fx * c10[1]) + fy * ((1 - fx) * c01[1] + fx * c11[1])};
      // A point of the aperture, uniform on the disk, for each sample.
      const double r = std::sqrt(jitter.uniform()), phi = 2 * std::numbers::pi * jitter.uniform();
      const std::array<double, 2> p = {r * std::cos(phi), r * std::sin(phi)};
      const std::array<double, 2> origin = {capture.camera_position[0] + radius * p[0],
                                            capture.camera_position[1] + radius * p[1]};
      const std::array<double, 2> slope = {t[0] - radius * p[0] * camera.focus_diopters,
                                           t[1] - radius * p[1] * camera.focus_diopters};
      for (size_t b = 0; b < truth.branches.size(); ++b) {
        double light = branch_scale[b];
        for (int l : truth.branches[b].layers) {
          const ShownPanel& panel = panels[l];
          const auto pixel_at = panel.PixelOfRay(origin, slope);
          light *= panel.at(pixel_at[0], pixel_at[1]);
          if (light == 0) break;
        }
        sum += light;
      }
    }
    signals[pixel] = gain * sum / samples;
  }
  return signals;
}

}  // namespace

PhotoRenderer::PhotoRenderer(const PhotoCamera& camera) : camera_(camera) {
  if (camera.width <= 0 || camera.height <= 0 || camera.supersampling <= 0)
    throw Error("the synthetic camera needs a positive image size and supersampling");
  if (static_cast<size_t>(camera.width) * static_cast<size_t>(camera.height) > kMaxPhotoPixels)
    throw Error("the synthetic camera's " + std::to_string(camera.width) + " x " + std::to_string(camera.height) +
                " pixels pass the limit of " + std::to_string(kMaxPhotoPixels));
  for (double v : {camera.white, camera.full_well, camera.read_noise, camera.aperture_m, camera.focus_diopters,
                   camera.response_gamma, camera.psf_sigma_px})
    if (!std::isfinite(v)) throw Error("the synthetic camera's settings must be finite");
  if (!(camera.white > 0) || camera.full_well < 0 || camera.read_noise < 0 || camera.aperture_m < 0 ||
      !(camera.response_gamma > 0) || camera.psf_sigma_px < 0 || camera.bits < 0 || camera.bits > 24)
    throw Error(
        "the synthetic camera needs white > 0, full well, read noise, aperture and blur >= 0, a response "
        "gamma > 0 and 0 to 24 bits");
  // The undistorted slope at every pixel corner; a sample's is interpolated between them (the
  // distortion is smooth: the error is far below a thousandth of a pixel).
  slopes_.resize(static_cast<size_t>(camera.width + 1) * (camera.height + 1) * 2);
  size_t k = 0;
  for (int v = 0; v <= camera.height; ++v)
    for (int u = 0; u <= camera.width; ++u) {
      const auto angle = AngleFromCameraPixel(camera.intrinsics, u - 0.5, v - 0.5);
      slopes_[k++] = angle ? std::tan((*angle)[0]) : NAN;
      slopes_[k++] = angle ? std::tan((*angle)[1]) : NAN;
    }
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

  Image image;
  image.width = camera_.width;
  image.height = camera_.height;
  image.channels = {"Y"};
  image.pixels.resize(static_cast<size_t>(camera_.width) * camera_.height);
  Gaussian noise(MixSeed(camera_.seed, seed_key));
  const double steps = camera_.bits > 0 ? std::ldexp(1.0, camera_.bits) - 1 : 0;
  std::vector<double> signals = PixelSignals(camera_, slopes_, truth, capture, panels, branch_scale, gain, seed_key);
  Blur(signals, camera_.width, camera_.height, camera_.psf_sigma_px);
  for (size_t pixel = 0; pixel < image.pixels.size(); ++pixel) {
    double signal = signals[pixel];
    if (camera_.full_well > 0) signal += std::sqrt(std::max(signal, 0.0) / camera_.full_well) * noise();
    if (camera_.read_noise > 0) signal += camera_.read_noise * noise();
    signal = std::clamp(signal, 0.0, 1.0);
    double value = camera_.response_gamma == 1 ? signal : std::pow(signal, 1 / camera_.response_gamma);
    if (steps > 0) value = std::round(value * steps) / steps;
    image.pixels[pixel] = static_cast<float>(value);
  }
  return image;
}

}  // namespace layerlab
