// The hybrid's outer iterations (paper Fig. 2) on a solve's loop, for the
// hybrid solver and for quasi-newton's warm start. Each iteration visits the
// sets in turn: a set's chase (the target minus the light of the other sets,
// solvers/hybrid_chase.h), then `sub_iterations` multiplicative updates of
// each of its layers toward it. A set of two layers whose rays are at least
// twice their pixel pairs (kernels/pair_lattice.h) bins its chase once and
// makes the updates after the first from the pairs: the same sums, a few
// pairs per pixel instead of every ray.
#pragma once

#include <optional>
#include <vector>

#include "layerlab/kernels/branch_pairs.h"
#include "layerlab/solvers/hybrid_chase.h"
#include "layerlab/solvers/solve_loop.h"

namespace layerlab {

class HybridIterations {
 public:
  // Allocates the chase (part of the solve's set-up, before loop.Start()).
  HybridIterations(const DisplayModel& model, const SolverOptions& options, Patterns* t);

  // After loop.Start(): the loop's target and workspace (sized with the
  // hybrid's passes), and whether the sets have emitted light already.
  void Begin(SolveLoop* loop);

  // One outer iteration. With `objective`, the iteration ends with the pass
  // that gives the objective of the patterns it leaves (and, on the one-tap
  // path, the next iteration's first update); that objective is returned
  // where the pass gives it. Without, an iteration after which the caller
  // evaluates the patterns itself (quasi-newton's last warm-start iteration).
  std::optional<double> Iterate(bool objective);

 private:
  const DisplayModel& model_;
  const SolverOptions& options_;
  Patterns* t_;
  HybridChase chase_;
  SolveWorkspace* workspace_ = nullptr;
  std::vector<std::optional<BranchPairs>> pairs_;
  LayerUpdate next_first_;
  bool next_first_ready_ = false;
};

}  // namespace layerlab
