// PNG images as linear light: libpng decodes the file's transfer curve
// (sRGB unless a gAMA chunk says otherwise) to linear values, and alpha is
// composited over black.
#pragma once

#include <string>

#include "framework/exr_image.h"

namespace layerlab {

// Channels R, G, B in [0, 1], row 0 at the top. Throws layerlab::Error naming the file.
Image ReadPngLinear(const std::string& path, long long max_pixels = 64ll << 20);

}  // namespace layerlab
