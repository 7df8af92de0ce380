// 8-bit PNG output, written atomically.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace layerlab {

// `pixels` is [row][col][channel] with 1 (gray), 3 (RGB) or 4 (RGBA) channels, row 0 at the top.
void WritePng8(const std::string& path, int width, int height, int channels, const std::vector<uint8_t>& pixels);

// A linear-light RGB image for viewing: value / white, sRGB-encoded (IEC
// 61966-2-1) to 8 bits. Returns how many values lay above white and were
// clipped, so that the caller can say so.
size_t WriteSrgbPng(const std::string& path, int width, int height, const std::vector<float>& rgb, double white = 1.0);

}  // namespace layerlab
