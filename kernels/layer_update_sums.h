// The sums of the non-negative multiplicative update of one layer `a` of one
// branch b (the step itself: solvers/multiplicative_update.h):
//   num = P_a^T(r o Q),   den = P_a^T(l~_b o Q),   Q = w_b prod_{k in b, k != a} P_k t_k
// over the rays of the light field, by the one-tap path (one_tap_update.h),
// the pixel-pair lattice (pair_lattice.h) or, for any projection, tap by tap.
#pragma once

#include <vector>

#include "layerlab/kernels/branch_target.h"
#include "layerlab/kernels/pair_lattice.h"
#include "layerlab/kernels/solve_workspace.h"
#include "layerlab/systems/display_model.h"
#include "layerlab/systems/mapped_pairs.h"

namespace layerlab {

// The sums of one update, apart from its step, so that the pass over the rays
// can be made early: the multiplicative solver makes the next iteration's
// first one in the pass that gives the objective.
// Layer `layer` of branch `branch`.
struct BranchLayer {
  size_t branch = 0;
  int layer = -1;
};

struct LayerUpdate {
  size_t branch = 0;
  int layer = -1;
  std::vector<double>*num, *den;  // layer pixels x 3, the ratio's two sides (in a workspace)
};
// The workspace's update kept for the next iteration, and the one of a single update.
inline LayerUpdate KeptLayerUpdate(SolveWorkspace* w) { return {0, -1, &w->kept_num, &w->kept_den}; }
inline LayerUpdate OneLayerUpdate(SolveWorkspace* w) { return {0, -1, &w->update_num, &w->update_den}; }
// The sums from the patterns `t` as they are now. With `error`, and if the
// branch is on the one-tap path, the same pass also gives the branch's
// squared error against `branch_target` (summed per view, then in view
// order); returns whether it did.
bool ComputeLayerUpdate(const DisplayModel& model, BranchLayer which, const BranchTarget& branch_target,
                        const Patterns& t, SolveWorkspace* workspace, LayerUpdate* update, double* error = nullptr);
// The same sums from the branch's target binned by pixel pair (PairLattice::Bin
// into `binned`); the layer is one of the lattice's two. In `workspace`, sized with kLayerUpdatePass.
void ComputeLayerUpdateFromPairs(const DisplayModel& model, BranchLayer which, const PairLattice& lattice,
                                 const PairCells& binned, const Patterns& t, SolveWorkspace* workspace,
                                 LayerUpdate* update);
// The same behind real lenses, from MappedPairs::Bin's `binned`.
void ComputeLayerUpdateFromMappedPairs(const DisplayModel& model, BranchLayer which, const MappedPairs& pairs,
                                       const std::vector<float>& binned, const Patterns& t, LayerUpdate* update);
}  // namespace layerlab
