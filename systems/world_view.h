// The world an optical see-through display is seen against (elements/world.cpp):
// natural light of a uniform luminance L_w through its path's efficiency e
// for unpolarized light (the mean of two orthogonal linear polarizations,
// exact for any Jones-calculus path), added at the eye to the display's
// light. The solve leaves it out: the target is what the display adds.
#pragma once

#include "layerlab/systems/display_system.h"

namespace layerlab {

// Sum over the worlds of L_w e, per channel (cd/m^2 at the eye); 0 without a world.
Rgb WorldAtEye(const DisplaySystem& system);

// Luminance-weighted (kLuminanceWeights).
double LuminanceOf(const Rgb& rgb);

// The ambient contrast ratio of the display's full white against the world, (L_peak + L_world) / L_world,
// luminance-weighted; +inf without a world.
double AmbientContrastRatio(const DisplaySystem& system);

}  // namespace layerlab
