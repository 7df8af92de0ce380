// The joint solver's pass (joint.cpp) for displays whose branches are all on
// the one-tap path (one_tap_view.h), in the layout of one_tap_update.h: view
// column by view column, every layer resampled once to the rays' columns,
// the per-ray work in contiguous rows, and the sums scattered to each layer's
// pixels once per view column. For every layer a of branch b it adds
//   res_a += P_a^T((l~ - l) o Q_a),  den_a += P_a^T(l~ o Q_a),   Q_a = w_b prod_{k in b, k != a} P_k t_k,
// with l~ the whole display's light, and returns ||l - l~||^2. Where the
// branches have equal layer counts, the light, the error and the sums of a
// ray row are made in one sweep (depth_sums_row.h), else the row's light
// first and then each branch's sums: the same bits. With `summed` ([layer],
// nonzero: sum it; exactly one layer of each branch, the branches of equal
// layer counts, else Error) only those layers' sums are made: the rank-K
// multiplicative solver updates one depth per pass; the others' are not
// written. Without `objective` the error is not computed and 0 is returned.
#pragma once

#include <vector>

#include "layerlab/framework/lightfield.h"
#include "layerlab/kernels/solve_workspace.h"
#include "layerlab/systems/display_model.h"

namespace layerlab {

// The pass's sums: res[k], den[k] layer k's pixels x 3, written (for the
// summed layers). (ColumnSums' num() holds res here.)
struct JointLayerSums {
  std::vector<std::vector<double>>* res;
  std::vector<std::vector<double>>* den;
};

// In `workspace`, sized with kJointPass.
double JointColumnPass(const DisplayModel& model, const LightField& l, const Patterns& t, JointLayerSums sums,
                       SolveWorkspace* workspace, const std::vector<char>* summed = nullptr, bool objective = true);

}  // namespace layerlab
