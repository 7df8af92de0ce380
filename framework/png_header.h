// A PNG file's size from its header (the IHDR chunk), read before any decoder
// allocates for it: a few hundred bytes can declare 30000 x 30000 pixels.
#pragma once

#include <cstddef>
#include <string>

namespace layerlab {

struct PngHeader {
  size_t width = 0, height = 0;
  int bit_depth = 0;  // 1, 2, 4, 8 or 16 bits per sample
  int channels = 0;   // as decoded: 1 gray, 2 gray + alpha, 3 RGB (and palette), 4 RGBA
};

// Checks the file kind first (framework/file_kind.h), then the signature and
// the IHDR chunk. Throws layerlab::Error naming the file.
PngHeader ReadPngHeader(const std::string& path);

// Refuses `header` when its width x height passes `max_pixels`, naming the file.
void RequirePngWithinLimit(const std::string& path, const PngHeader& header, size_t max_pixels);

}  // namespace layerlab
