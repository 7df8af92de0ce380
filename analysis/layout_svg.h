// A side view of a display's optical path, unfolded from the eye, as SVG:
// one row per branch drawn to scale (eye, lenses, mirrors, combiners, in-line
// optics, panels at their path lengths from the pupil), and below it the
// panels' images in eye space on a diopter axis, each joined to its panel.
#pragma once

#include <string>

#include "layerlab/systems/display_system.h"

namespace layerlab {

// `standalone` adds the XML namespace a .svg file needs (HTML's inline SVG does not).
std::string RenderLayoutSvg(const DisplaySystem& system, bool standalone = true);

}  // namespace layerlab
