// A wave plate (a linear retarder) for the in-line optics hwp and qwp: a
// plate of `waves` (1/2, 1/4) at its design wavelength lambda0, zero order
// m, has retardance (m + waves) 2 pi lambda0 / lambda (the birefringence's
// own dispersion ignored); an achromatic plate has waves 2 pi at every
// wavelength. Its keys are the hwp's and qwp's tables.
#pragma once

#include <memory>

#include "layerlab/elements/element.h"

namespace layerlab {

std::unique_ptr<Element> MakeWavePlate(Params& p, double waves);

}  // namespace layerlab
