// What the eye sees of a display with a folded path: its branches and its
// ghosts (systems/display_system.h, Ghost), each ghost a branch of its own
// that shows the patterns of the stack it repeats. The solvers' display
// leaves the ghosts out; the retinal images use this one.
#pragma once

#include <vector>

#include "layerlab/systems/display_model.h"

namespace layerlab {

struct GhostedDisplay {
  DisplaySystem system;         // the display's layers and the ghosts' (farthest first), its branches and theirs
  std::vector<int> pattern_of;  // per layer of `system`: the display's layer whose pattern it shows
};

// `system` itself (pattern_of the identity) when it has no ghosts.
GhostedDisplay WithGhosts(const DisplaySystem& system);

// Each layer's pattern of the ghosted display, from the display's own.
Patterns GhostedPatterns(const GhostedDisplay& ghosted, const Patterns& patterns);

}  // namespace layerlab
