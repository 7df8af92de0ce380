// Natural viewing of a light-field target: the radiance along any ray that
// crosses the eyebox, read from the light field itself.
//
// The ray from pupil point u with tan-direction d crosses the origin plane at
// x = u + d z_lf (docs/lightfield-format.md); its value is the light field
// interpolated bilinearly over the four views around u and, in each, over
// the four pixels around x. A pupil point outside the eyebox reads the
// nearest edge views; a ray outside the window reads 0. A 4 mm pupil inside
// the paper's 6 mm eyebox of 13 x 13 views needs no extrapolation.
#pragma once

#include "framework/lightfield.h"
#include "systems/retina.h"

namespace layerlab {

// The returned function refers to `lf`, which must outlive it.
SceneRadiance LightFieldRadiance(const LightField& lf);

}  // namespace layerlab
