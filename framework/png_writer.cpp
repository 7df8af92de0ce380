#include "layerlab/framework/png_writer.h"

#include <png.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "layerlab/framework/atomic_file.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/srgb_code.h"

namespace layerlab {

void WritePng8(const std::string& path, int width, int height, int channels, const std::vector<uint8_t>& pixels,
               PngCompression compression, double pixels_per_meter) {
  if (width <= 0 || height <= 0 || (channels != 1 && channels != 3 && channels != 4) ||
      pixels.size() != static_cast<size_t>(width) * height * channels)
    throw Error(path + ": internal error: PNG buffer does not match its size");
  AtomicFile out(path);
  FILE* file = std::fopen(out.temp_path().c_str(), "wb");
  if (!file) throw Error(path + ": cannot open for writing: " + std::strerror(errno));
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  volatile bool ok = png && info;  // survives longjmp
  if (ok && setjmp(png_jmpbuf(png)) == 0) {
    png_init_io(png, file);
    if (compression == PngCompression::kFast) png_set_compression_level(png, 1);
    int type = channels == 1 ? PNG_COLOR_TYPE_GRAY : channels == 3 ? PNG_COLOR_TYPE_RGB : PNG_COLOR_TYPE_RGBA;
    png_set_IHDR(png, info, width, height, 8, type, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
                 PNG_FILTER_TYPE_DEFAULT);
    if (pixels_per_meter > 0 && pixels_per_meter < 4e9) {
      const auto ppm = static_cast<png_uint_32>(std::lround(pixels_per_meter));
      png_set_pHYs(png, info, ppm, ppm, PNG_RESOLUTION_METER);
    }
    png_write_info(png, info);
    for (int row = 0; row < height; ++row)
      png_write_row(png, const_cast<png_bytep>(pixels.data() + static_cast<size_t>(row) * width * channels));
    png_write_end(png, nullptr);
  } else {
    ok = false;
  }
  png_destroy_write_struct(png ? &png : nullptr, info ? &info : nullptr);
  bool closed = std::fclose(file) == 0;
  if (!ok || !closed) throw Error(path + ": cannot write PNG (disk full?)");
  out.Commit();
}

size_t WriteSrgbPng(const std::string& path, int width, int height, const std::vector<float>& rgb, double white,
                    PngCompression compression) {
  if (!(white > 0)) throw Error(path + ": internal error: white must be positive");
  std::vector<uint8_t> pixels(rgb.size());
  size_t clipped = 0;
  for (size_t k = 0; k < rgb.size(); ++k) {
    double v = rgb[k] / white;
    if (v > 1) ++clipped;
    pixels[k] = SrgbCode(v);
  }
  WritePng8(path, width, height, 3, pixels, compression);
  return clipped;
}

}  // namespace layerlab
