// 8-bit PNG output, written atomically.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace layerlab {

// zlib's effort: kSmallest is its default (level 6); kFast (level 1) writes a
// 710 x 364 retinal image in about a fifth of the time, 20% larger.
enum class PngCompression { kSmallest, kFast };

// `pixels` is [row][col][channel] with 1 (gray), 3 (RGB) or 4 (RGBA) channels, row 0 at the top.
// `pixels_per_meter` > 0 is stored as the image's physical resolution (pHYs), so that it prints at its size.
void WritePng8(const std::string& path, int width, int height, int channels, const std::vector<uint8_t>& pixels,
               PngCompression compression = PngCompression::kSmallest, double pixels_per_meter = 0);

// A linear-light RGB image for viewing: value / white, sRGB-encoded (IEC
// 61966-2-1) to 8 bits. Returns how many values lay above white and were
// clipped, so that the caller can say so.
size_t WriteSrgbPng(const std::string& path, int width, int height, const std::vector<float>& rgb, double white = 1.0,
                    PngCompression compression = PngCompression::kSmallest);

}  // namespace layerlab
