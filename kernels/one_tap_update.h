// The sums of the multiplicative update (multiplicative_update.h) for a
// branch on the one-tap path (one_tap_view.h), with w_b and t_a factored out:
//   num[pixel][c] += sum r q,   den[pixel][c] += sum q^2,   q = prod_{k != a} P_k t_k
// over the rays that read `pixel` of layer a.
//
// View column by view column: within one, each layer's column depends on the
// ray's column alone, so every other layer is resampled once to the rays'
// columns (its rows x the light field's columns). The sums then accumulate in
// the rays' columns, row by row over the column's views, in contiguous vector
// loops without a per-ray index; they reach layer a's pixels in one scatter
// per view column.
#pragma once

#include <array>
#include <vector>

#include "layerlab/kernels/branch_target.h"
#include "layerlab/kernels/solve_workspace.h"
#include "layerlab/systems/display_model.h"

namespace layerlab {

// A branch as the update reads it: its layers, the updated layer a first,
// and its weight w_b.
struct UpdatedBranch {
  const std::vector<int>& layers;
  std::array<float, 3> weight;
};

// What the update's pass writes: num and den hold layer a's pixels x 3. With
// `view_errors` (one per view), the same pass also gives each view's sum of
// (r - w_b prod_k P_k t_k)^2 over its rays and channels, the branch's own
// error against what it should emit.
struct OneTapSums {
  double* num;
  double* den;
  double* view_errors = nullptr;
};

// In `workspace`, sized with kLayerUpdatePass.
void OneTapUpdateSums(const DisplayModel& model, const UpdatedBranch& branch, const Patterns& t,
                      const BranchTarget& branch_target, OneTapSums sums, SolveWorkspace* workspace);

}  // namespace layerlab
