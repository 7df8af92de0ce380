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

#include <vector>

#include "layerlab/kernels/branch_pairs.h"
#include "layerlab/kernels/layer_update_sums.h"
#include "layerlab/solvers/types.h"

namespace layerlab {

// In `workspace`, sized with kLayerUpdatePass.
void UpdateLayerMultiplicative(const DisplayModel& model, size_t branch, int layer, const BranchTarget& branch_target,
                               const SolverOptions& options, Patterns* t, SolveWorkspace* workspace);

// The same update from the branch's target binned by pixel pair (ComputeLayerUpdateFromPairs).
void UpdateLayerFromPairs(const DisplayModel& model, size_t branch, int layer, const BranchPairs& pairs,
                          const SolverOptions& options, Patterns* t, SolveWorkspace* workspace);
// Applies it to patterns in which nothing has changed since it was computed.
void ApplyLayerUpdate(const LayerUpdate& update, const SolverOptions& options, Patterns* t);

// The step itself: pattern[k] <- clamp(pattern[k] num[k] / den[k], floor, 1)
// where den[k] > epsilon (else it keeps its value); num and den as long as the pattern.
void ApplyMultiplicativeStep(const double* num, const double* den, const SolverOptions& options,
                             std::vector<float>* pattern);
// The ratio num / den from the joint pass's sums (kernels/joint_pass.h): num = den - res.
inline double MultiplicativeRatioFromResidual(double res, double den) { return (den - res) / den; }
// The same step from those sums.
void ApplyMultiplicativeStepFromResidual(const double* res, const double* den, const SolverOptions& options,
                                         std::vector<float>* pattern);

}  // namespace layerlab
