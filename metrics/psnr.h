// Peak signal-to-noise ratio, peak 1 (display-relative light: 1 is the
// display's white): 10 log10(1 / MSE), the mean over every value compared.
#pragma once

#include <cstddef>

#include "layerlab/framework/exr_image.h"

namespace layerlab {

struct Plane;  // ssim.h

// From a sum of squared errors over `samples` values; +inf for no error.
double PsnrDb(double squared_error, size_t samples);

// Of two images of one size over every pixel and channel, the squared
// errors summed in double in a fixed order (the same bits on any machine).
// Throws layerlab::Error for images of different sizes or channel counts.
// With `weight` (one per pixel, ssim.h's Plane; foveal_weight.h) the mean is weighted by it.
double ImagePsnrDb(const Image& test, const Image& reference, const Plane* weight = nullptr);

}  // namespace layerlab
