// What the eye sees of a backlight's LED array (elements/backlight.cpp,
// EmitterSpec): each LED's light spread by the diffuser in front of it. The
// LED layer is a fine grid of pitch h = led_pitch / stride whose solved
// values sit at the centre pixel of each LED's stride x stride cell (0
// elsewhere); the emission is that grid convolved with the spread g, a
// Gaussian of the given FWHM sampled at the grid's pixels along each axis
// (separable), scaled so that its taps sum to the stride:
//   B(x) = sum_k L_k s g(x - x_k) / sum_d g(d h)   per axis,
// so that LEDs all at 1 emit 1 on average over a cell, the backlight's
// luminance. The layer's sampling then interpolates B between grid pixels
// (at least 4 across the FWHM). Beyond the array's edge the emission is 0.
// The approximations: a Gaussian spread (a diffuser's, far from the LEDs;
// a measured spread function is not read), the same for every LED and
// channel, cut at 4 sigma.
#pragma once

#include <vector>

#include "layerlab/systems/display_system.h"
#include "layerlab/systems/panel_diffraction.h"

namespace layerlab {

// Kernels beyond this many sigma are cut (the Gaussian's tail beyond holds 6e-5 of its light).
inline constexpr double kSpreadSigmas = 4.0;

// One entry per LED layer, its spread along x and y (LayerDiffraction's form, panel_layer = the layer
// itself, gap 0); none when no backlight has LEDs.
std::vector<LayerDiffraction> SourceSpread(const DisplaySystem& system);

// What the eye sees of the layers, in the order they apply: every LED array's spread, then (with
// `panel_diffraction`) the panels' diffraction (PanelDiffraction). Empty when neither changes a pattern.
std::vector<LayerDiffraction> SeenKernels(const DisplaySystem& system, bool panel_diffraction);

// Whether layer k is an LED array whose values are solved (and held at its sites).
bool IsSolvedEmitter(const VirtualLayer& layer);

// An LED layer's values, one pixel per LED (led_cols x led_rows, in the layer's own order): what drives them.
LayerPattern LedValues(const VirtualLayer& layer, const LayerPattern& pattern);

// Sets every pixel of an LED layer's pattern that is not an LED site to 0 (its rows x cols x 3 values);
// a layer of another kind is left as it is.
void KeepEmitterSites(const VirtualLayer& layer, std::vector<float>* rgb);

}  // namespace layerlab
