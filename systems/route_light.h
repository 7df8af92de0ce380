// The light of one route from a panel (or the world) to the eye: what each
// element on it does to light (Jones calculus per channel where polarization
// is tracked, framework/polarization.h), and the most any light can pass it.
#pragma once

#include <array>
#include <vector>

#include "layerlab/elements/element.h"

namespace layerlab {

// An element that acts on light on its way to the eye; for a combiner, what it
// does there: transmit (kTransmittedPort) or reflect (kReflectedPort).
struct LightStep {
  const Element* element;
  size_t action;
};

// Applies `step` to light travelling toward the eye; a real lens loses light
// at its surfaces and in its glass (per channel, at `wavelengths_m`).
void ApplyLightStep(const LightStep& step, const std::array<double, 3>& wavelengths_m, Light& light);

// The largest fraction of light, over every channel and every polarization
// entering it, that `route` (nearest the eye first) passes: the largest
// singular value squared of its Jones matrix.
double BrightestThrough(const std::vector<LightStep>& route, const std::array<double, 3>& wavelengths_m);

}  // namespace layerlab
