// Natural viewing of a light-field target: the radiance along any ray that
// crosses the eyebox, read from the light field itself.
//
// The ray from pupil point u with tan-direction d crosses the origin plane at
// x = u + d z_lf (docs/lightfield-format.md). Its value is interpolated
// bilinearly over the four views around u, and in each view read at x by the
// layers' sampling rule (layer_sampler.h): nearest (the default, as the
// display's layers are read) holds the pixel containing x, bilinear blends the
// four pixel centers around it. So a one-layer display on the origin plane
// whose pixels are the light field's is seen exactly as natural viewing of its
// own light field, under either rule. A pupil point outside the eyebox reads
// the nearest edge views; a ray outside the window reads 0. A 4 mm pupil
// inside the paper's 6 mm eyebox of 13 x 13 views needs no extrapolation.
#pragma once

#include "framework/lightfield.h"
#include "systems/layer_sampler.h"
#include "systems/retina.h"

namespace layerlab {

// The returned function refers to `lf`, which must outlive it.
SceneRadiance LightFieldRadiance(const LightField& lf, Sampling pixels = Sampling::kNearest);

}  // namespace layerlab
