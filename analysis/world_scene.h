// The light of a see-through display's worlds (systems/world_view.h) along
// any ray from the pupil, for the retinal images: each world's luminance
// times its path's efficiency, times its scene's radiance where it has one
// (a target scene traced ray by ray with Embree, elements/world.cpp).
#pragma once

#include "layerlab/retina/scene_radiance.h"
#include "layerlab/systems/display_system.h"

namespace layerlab {

// cd/m^2 at the eye per channel along a ray; empty when no world has a scene (the uniform worlds are then
// WorldAtEye, the same along every ray). Throws layerlab::Error naming the file for a scene that does not
// read, or when this build has no Embree.
SceneRadiance WorldSceneRadiance(const DisplaySystem& system);

}  // namespace layerlab
