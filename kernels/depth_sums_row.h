// One ray row of the joint pass over branches of equal layer counts, in one
// sweep. For B branches of L layers each, rows[b * L + k] the ray row of
// branch b's k-th member, every one reached by the rays:
//   light[j] = sum_b w_b prod_k rows[b][k][j]              (from 0, branch by branch)
//   q = w_b prod_{k != a} rows[b][k][j],  res[.][j] += (light[j] - l_j) q,  den[.][j] += light[j] q
// with the display's light kept in a register, and if asked the row's
// squared error sum_j ||l_j - light[j]||^2. The sums are made for every
// member a of every branch (the joint and quasi-newton passes), or for one
// member a_b of each (a one-depth pass: the rank-K multiplicative solver
// updates one layer of each subframe's branch per pass; the others' sums are
// not made). The operations are AddBranchLightRow's, branch by branch, then
// JointSumsRow's (q multiplied from the front up to a and from the back down
// to it) and SquaredErrorRow's, so the sums and the error are the bits of
// those kernels run one after another.
#pragma once

#include "layerlab/framework/rgb4.h"
#include "layerlab/kernels/row_args.h"

namespace layerlab {

// `branches` of 1 to 4 layers each (kMaxOneTapLayers), their rows one after
// another (stride == layers), over the rays j < cols. With `a`
// (0 <= a[b] < layers), sums.res[b] and sums.den[b] are branch b's member
// a[b]'s; with a == nullptr, sums.res[b * layers + k] and sums.den[b * layers
// + k] are every member k's. `squared_error` written if not null (in double,
// channels 0-2, as SquaredErrorRow sums it; no branch: the light is 0).
void DepthSumsRow(BranchRows branches, int cols, const int* a, PackedRow l, double* squared_error, MemberRowSums sums);

}  // namespace layerlab
