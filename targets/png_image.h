// PNG images as linear light: libpng reduces the file to 8-bit sRGB (it
// converts a file with another gAMA, expands palettes and gray, and
// composites alpha over black), and the exact sRGB curve (IEC 61966-2-1)
// decodes it. 16-bit files lose their low bits: give high-precision
// textures as EXR.
#pragma once

#include <string>

#include "layerlab/framework/exr_image.h"

namespace layerlab {

// Channels R, G, B in [0, 1], row 0 at the top. Throws layerlab::Error naming the file.
Image ReadPngLinear(const std::string& path, long long max_pixels = 64ll << 20);

// The sRGB decoding curve, for an encoded value in [0, 1].
double SrgbToLinear(double encoded);

}  // namespace layerlab
