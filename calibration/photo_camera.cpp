#include "layerlab/calibration/photo_camera.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "layerlab/calibration/capture_plan.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/random.h"

namespace layerlab {
namespace {

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

}  // namespace

void CheckPhotoCamera(const PhotoCamera& camera) {
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
}

std::vector<double> PixelCornerSlopes(const PhotoCamera& camera) {
  std::vector<double> slopes(static_cast<size_t>(camera.width + 1) * (camera.height + 1) * 2);
  size_t k = 0;
  for (int v = 0; v <= camera.height; ++v)
    for (int u = 0; u <= camera.width; ++u) {
      const auto angle = AngleFromCameraPixel(camera.intrinsics, u - 0.5, v - 0.5);
      slopes[k++] = angle ? std::tan((*angle)[0]) : NAN;
      slopes[k++] = angle ? std::tan((*angle)[1]) : NAN;
    }
  return slopes;
}

std::vector<double> PixelSignals(const PhotoCamera& camera, const std::vector<double>& slopes, uint64_t seed_key,
                                 const RayLight& light) {
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
      const std::array<double, 2> origin = {radius * r * std::cos(phi), radius * r * std::sin(phi)};
      sum += light(origin, {t[0] - origin[0] * camera.focus_diopters, t[1] - origin[1] * camera.focus_diopters});
    }
    signals[pixel] = sum / samples;
  }
  return signals;
}

Image RecordOnSensor(const PhotoCamera& camera, std::vector<double> signals, uint64_t seed_key) {
  Image image;
  image.width = camera.width;
  image.height = camera.height;
  image.channels = {"Y"};
  image.pixels.resize(static_cast<size_t>(camera.width) * camera.height);
  Gaussian noise(MixSeed(camera.seed, seed_key));
  const double steps = camera.bits > 0 ? std::ldexp(1.0, camera.bits) - 1 : 0;
  Blur(signals, camera.width, camera.height, camera.psf_sigma_px);
  for (size_t pixel = 0; pixel < image.pixels.size(); ++pixel) {
    double signal = signals[pixel];
    if (camera.full_well > 0) signal += std::sqrt(std::max(signal, 0.0) / camera.full_well) * noise();
    if (camera.read_noise > 0) signal += camera.read_noise * noise();
    signal = std::clamp(signal, 0.0, 1.0);
    double value = camera.response_gamma == 1 ? signal : std::pow(signal, 1 / camera.response_gamma);
    if (steps > 0) value = std::round(value * steps) / steps;
    image.pixels[pixel] = static_cast<float>(value);
  }
  return image;
}

}  // namespace layerlab
