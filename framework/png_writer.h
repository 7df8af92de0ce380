// 8-bit PNG output, written atomically.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace layerlab {

// `pixels` is [row][col][channel] with 1 (gray), 3 (RGB) or 4 (RGBA) channels, row 0 at the top.
void WritePng8(const std::string& path, int width, int height, int channels, const std::vector<uint8_t>& pixels);

}  // namespace layerlab
