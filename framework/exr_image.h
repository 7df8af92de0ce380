// OpenEXR images: linear float pixels, interleaved channels. Reading checks
// the header before allocating (OpenEXR sets no size limit of its own) and
// refuses non-finite or negative values, naming the file, pixel and channel.
#pragma once

#include <string>
#include <vector>

namespace layerlab {

struct Image {
  int width = 0, height = 0;
  std::vector<std::string> channels;  // e.g. {"R", "G", "B"} or {"Z"}
  std::vector<float> pixels;          // [row][col][channel], row 0 at the top

  float at(int row, int col, int channel) const {
    return pixels[(static_cast<size_t>(row) * width + col) * channels.size() + channel];
  }
};

struct ExrLimits {
  long long max_pixels = 64ll << 20;  // 64 Mpixel
};

// Light is finite and non-negative. The first of `count` interleaved values
// (`channels` per pixel, `width` pixels per row) that is not, as "pixel (row
// 2, col 3) channel G is NaN; light must be finite and non-negative"; "" when
// every value is light. ReadExr refuses a file with it, the Python module an array.
std::string FindValueThatIsNotLight(const float* values, size_t count, int width,
                                    const std::vector<std::string>& channels);

// Reads the named channels (all must exist; half or float). Throws layerlab::Error.
Image ReadExr(const std::string& path, const std::vector<std::string>& channels, const ExrLimits& limits = {});

// How WriteExr stores the pixels. ZIP takes a 710 x 364 RGB float image
// (a retinal image) from 3.11 to 2.94 MB in about 80 ms; stored as they are
// it takes about 5 ms.
enum class ExrCompression { kZip, kNone };

// How WriteExr stores each value: as it is (32-bit float), or as a 16-bit
// half (11 significant bits: a relative error of at most 2^-11 = 0.049 %,
// values up to 65504), half the size; for pictures to look at, not for values
// to compute with again.
enum class ExrPixels { kFloat, kHalf };

// Writes float channels, atomically. kHalf refuses a value beyond the largest
// half rather than write it as infinity.
void WriteExr(const std::string& path, const Image& image, ExrCompression compression = ExrCompression::kZip,
              ExrPixels pixels = ExrPixels::kFloat);

// The data window size of an EXR file without reading its pixels.
struct ExrSize {
  int width, height;
};
ExrSize ReadExrSize(const std::string& path);

// The names of an EXR file's channels, without reading its pixels.
std::vector<std::string> ReadExrChannelNames(const std::string& path);

}  // namespace layerlab
