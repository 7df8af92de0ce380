#pragma once

#include "layerlab/systems/display_system.h"
#include "layerlab/systems/scene.h"

namespace layerlab {

// Walks the optical path from the eye outward (eye -> main lens -> combiners
// and in-line optics -> panel stacks -> backlights) and builds the optically
// equivalent system. Refuses, with the element's JSON pointer: a missing or
// second eye, dangling, cyclic or shared connections, an element of the wrong
// kind in a slot, elements off the path, a panel beyond the focal plane, and
// two panels of one stack at the same depth or out of order.
DisplaySystem Compile(const Scene& scene);

// A thin lens is warned of (DisplaySystem::warnings) when a layer is seen through it over a wider field than
// this (deg, either axis), or when it is faster than this f-number: first-order optics no longer describes it.
inline constexpr double kFirstOrderFieldDeg = 60;
inline constexpr double kFirstOrderFNumber = 1;

}  // namespace layerlab
