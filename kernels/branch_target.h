// What a branch should emit, view by view: the input of the multiplicative
// update's sums (layer_update_sums.h, one_tap_update.h).
#pragma once

#include <cstddef>
#include <functional>

namespace layerlab {

// What the branch should emit in one view ([row][col][rgb]): a pointer to
// stored values, or to `scratch` after filling it.
using BranchTarget = std::function<const float*(size_t view, float* scratch)>;

}  // namespace layerlab
