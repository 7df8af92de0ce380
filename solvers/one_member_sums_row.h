// The joint pass's sums (systems/row_kernels.h, JointSumsRow) for one member
// a of a branch only: the rank-K multiplicative solver updates one depth per
// pass, one layer of each subframe's branch, and the other members' sums
// would be thrown away. Over one ray row,
//   q = w prod_{k != a} rows[k][j],  num[j] += l_j q,  den[j] += light[j] q,
// with q multiplied in JointSumsRow's order (the members before a from the
// front, those after a from the back), so that the sums are its bits.
#pragma once

#include "framework/rgb4.h"

namespace layerlab {

// `layers` 1 to 4 (kMaxOneTapLayers), 0 <= a < layers; l packed, its last ray read exactly if `exact_last`.
void OneMemberSumsRow(const Rgb4* const* rows, int layers, int a, Rgb4 w, int cols, const float* l, bool exact_last,
                      const Rgb4* light, Rgb4* num, Rgb4* den);

}  // namespace layerlab
