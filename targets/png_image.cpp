#include "layerlab/targets/png_image.h"

#include <array>
#include <cmath>
#include <cstring>
#include <vector>

#include <png.h>

#include "layerlab/framework/error.h"

namespace layerlab {

double SrgbToLinear(double encoded) {
  return encoded <= 0.04045 ? encoded / 12.92 : std::pow((encoded + 0.055) / 1.055, 2.4);
}

Image ReadPngLinear(const std::string& path, long long max_pixels) {
  png_image png;
  std::memset(&png, 0, sizeof png);
  png.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&png, path.c_str())) throw Error(path + ": cannot read PNG: " + png.message);
  if (static_cast<long long>(png.width) * png.height > max_pixels) {
    std::string size = std::to_string(png.width) + " x " + std::to_string(png.height);
    png_image_free(&png);
    throw Error(path + ": is " + size + " pixels; the limit is " + std::to_string(max_pixels));
  }
  png.format = PNG_FORMAT_RGB;
  std::vector<png_byte> buffer(PNG_IMAGE_SIZE(png));
  png_color black = {0, 0, 0};
  if (!png_image_finish_read(&png, &black, buffer.data(), 0, nullptr)) {
    std::string message = png.message;
    png_image_free(&png);
    throw Error(path + ": cannot decode PNG: " + message);
  }
  std::array<float, 256> linear;
  for (int i = 0; i < 256; ++i) linear[i] = static_cast<float>(SrgbToLinear(i / 255.0));
  Image image;
  image.width = static_cast<int>(png.width);
  image.height = static_cast<int>(png.height);
  image.channels = {"R", "G", "B"};
  image.pixels.resize(buffer.size());
  for (size_t i = 0; i < buffer.size(); ++i) image.pixels[i] = linear[buffer[i]];
  return image;
}

}  // namespace layerlab
