// Every display's layer order: farthest first (ascending diopters, ties in
// the order met), as the paper numbers its panels.
#pragma once

#include <vector>

#include "layerlab/systems/display_system.h"

namespace layerlab {

// Sorts `system`'s layers farthest first and renumbers its branches' layers;
// returns, per new position, the layer's index before.
std::vector<int> SortLayersFarthestFirst(DisplaySystem* system);

}  // namespace layerlab
