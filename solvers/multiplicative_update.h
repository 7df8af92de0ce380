// The non-negative multiplicative update (Lee-Seung, as in tensor displays)
// of one layer `a` of one branch b, weighted per channel:
//   Q   = w_b prod_{k in b, k != a} P_k t_k           (the rest of the branch)
//   t_a <- clamp(t_a * P_a^T(r o Q) / P_a^T(l~_b o Q), floor, 1),   l~_b = Q o P_a t_a
// where r is what the branch should emit (the target, or for the hybrid
// algorithm the target minus the other branches, floored at 0). It is the
// ratio of the negative and positive parts of the gradient of ||r - l~_b||^2,
// so for r >= 0 it never increases that error. A pixel whose denominator is
// below epsilon (no ray reaches it, or the rest of the branch is black there)
// keeps its value.
#pragma once

#include <functional>
#include <vector>

#include "solvers/solver.h"
#include "systems/display_model.h"
#include "systems/pair_lattice.h"
#include "systems/solve_workspace.h"

namespace layerlab {

// What the branch should emit in one view ([row][col][rgb]): a pointer to
// stored values, or to `scratch` after filling it.
using BranchTarget = std::function<const float*(size_t view, float* scratch)>;

// In `workspace`, sized with kLayerUpdatePass.
void UpdateLayerMultiplicative(const DisplayModel& model, size_t branch, int layer, const BranchTarget& branch_target,
                               const SolverOptions& options, Patterns* t, SolveWorkspace* workspace);

// The same update in two steps, so that its pass over the rays can be made
// early: the multiplicative solver makes the next iteration's first one in
// the pass that gives the objective.
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
bool ComputeLayerUpdate(const DisplayModel& model, size_t branch, int layer, const BranchTarget& branch_target,
                        const Patterns& t, SolveWorkspace* workspace, LayerUpdate* update, double* error = nullptr);
// The same sums from the branch's target binned by pixel pair (PairLattice::Bin
// into `binned`); `layer` is one of the lattice's two. In `workspace`, sized with kLayerUpdatePass.
void ComputeLayerUpdateFromPairs(const DisplayModel& model, size_t branch, int layer, const PairLattice& lattice,
                                 const PairCells& binned, const Patterns& t, SolveWorkspace* workspace,
                                 LayerUpdate* update);
// UpdateLayerMultiplicative's update made so.
void UpdateLayerFromPairs(const DisplayModel& model, size_t branch, int layer, const PairLattice& lattice,
                          const PairCells& binned, const SolverOptions& options, Patterns* t,
                          SolveWorkspace* workspace);
// Applies it to patterns in which nothing has changed since it was computed.
void ApplyLayerUpdate(const LayerUpdate& update, const SolverOptions& options, Patterns* t);

// The step itself: pattern[k] <- clamp(pattern[k] num[k] / den[k], floor, 1)
// where den[k] > epsilon (else it keeps its value); num and den as long as the pattern.
void ApplyMultiplicativeStep(const double* num, const double* den, const SolverOptions& options,
                             std::vector<float>* pattern);
// The ratio num / den from the joint pass's sums (joint_pass.h): num = den - res.
inline double MultiplicativeRatioFromResidual(double res, double den) { return (den - res) / den; }
// The same step from those sums.
void ApplyMultiplicativeStepFromResidual(const double* res, const double* den, const SolverOptions& options,
                                         std::vector<float>* pattern);

}  // namespace layerlab
