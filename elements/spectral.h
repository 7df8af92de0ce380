// Wavelength-dependent efficiencies, evaluated at the color channels.
#pragma once

#include <string>

#include "layerlab/framework/params.h"

namespace layerlab {

// Reads a fraction per color channel given as one number, "95 %", an
// [r, g, b] triple, or a table {"wavelengths": ["450 nm", ...], "values":
// [0.9, ...]} interpolated linearly at kChannelWavelengths. A table that does
// not cover a channel's wavelength is refused (no silent extrapolation).
Rgb ReadSpectralFraction(Params& params, const std::string& key, double fallback);

}  // namespace layerlab
