#include "layerlab/framework/shown_image.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <type_traits>

#include "layerlab/framework/error.h"

namespace layerlab {
namespace {

template <typename T>
ShownImage<T> Shrink(int width, int height, int channels, const std::vector<T>& pixels, int max_width) {
  if (width < 1 || height < 1 || channels < 1 || max_width < 1 ||
      pixels.size() != static_cast<size_t>(width) * height * channels)
    throw Error("ShrinkToWidth: an image of " + std::to_string(width) + " x " + std::to_string(height) + " x " +
                std::to_string(channels) + " needs that many values, not " + std::to_string(pixels.size()));
  ShownImage<T> shown;
  shown.factor = ShrinkFactor(width, max_width);
  const int k = shown.factor;
  if (k == 1) {
    shown.width = width, shown.height = height, shown.pixels = pixels;
    return shown;
  }
  shown.width = (width + k - 1) / k, shown.height = (height + k - 1) / k;
  shown.pixels.resize(static_cast<size_t>(shown.width) * shown.height * channels);
  std::vector<double> sum(channels);
  for (int r = 0; r < shown.height; ++r)
    for (int c = 0; c < shown.width; ++c) {
      std::fill(sum.begin(), sum.end(), 0.0);
      const int r1 = std::min(height, (r + 1) * k), c1 = std::min(width, (c + 1) * k);
      for (int y = r * k; y < r1; ++y)
        for (int x = c * k; x < c1; ++x)
          for (int ch = 0; ch < channels; ++ch) sum[ch] += pixels[(static_cast<size_t>(y) * width + x) * channels + ch];
      const double n = static_cast<double>(r1 - r * k) * (c1 - c * k);
      for (int ch = 0; ch < channels; ++ch) {
        T& out = shown.pixels[(static_cast<size_t>(r) * shown.width + c) * channels + ch];
        if constexpr (std::is_integral_v<T>)
          out = static_cast<T>(std::lround(sum[ch] / n));
        else
          out = static_cast<T>(sum[ch] / n);
      }
    }
  return shown;
}

}  // namespace

int ShrinkFactor(int width, int max_width) {
  if (width < 1 || max_width < 1) return 1;
  return (width + max_width - 1) / max_width;
}

ShownImage<float> ShrinkToWidth(int width, int height, int channels, const std::vector<float>& pixels, int max_width) {
  return Shrink(width, height, channels, pixels, max_width);
}

ShownImage<uint8_t> ShrinkToWidth(int width, int height, int channels, const std::vector<uint8_t>& pixels,
                                  int max_width) {
  return Shrink(width, height, channels, pixels, max_width);
}

ShownPng WriteShownSrgbPng(const std::string& path, int width, int height, const std::vector<float>& rgb, int max_width,
                           PngCompression compression) {
  if (ShrinkFactor(width, max_width) == 1)
    return {width, height, 1, WriteSrgbPng(path, width, height, rgb, 1.0, compression)};
  const ShownImage<float> shown = ShrinkToWidth(width, height, 3, rgb, max_width);
  return {shown.width, shown.height, shown.factor,
          WriteSrgbPng(path, shown.width, shown.height, shown.pixels, 1.0, compression)};
}

ShownPng WriteShownPng8(const std::string& path, int width, int height, const std::vector<uint8_t>& rgb,
                        int max_width) {
  if (ShrinkFactor(width, max_width) == 1) {
    WritePng8(path, width, height, 3, rgb);
    return {width, height, 1, 0};
  }
  const ShownImage<uint8_t> shown = ShrinkToWidth(width, height, 3, rgb, max_width);
  WritePng8(path, shown.width, shown.height, 3, shown.pixels);
  return {shown.width, shown.height, shown.factor, 0};
}

}  // namespace layerlab
