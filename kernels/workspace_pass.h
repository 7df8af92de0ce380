// The kinds of pass over the rays a solve makes: a solver states its own
// (SolverMemory::passes, solvers/types.h) and the solve loop sizes the
// workspace (solve_workspace.h) for them alone.
#pragma once

namespace layerlab {

enum WorkspacePass : unsigned {
  kSynthesisPass = 1,            // the objective, the hybrid's chase (ViewSynthesizer)
  kLayerUpdatePass = 2,          // one layer's multiplicative-update sums (layer_update_sums.h)
  kJointPass = 4,                // every layer's sums at once (joint_pass.h)
  kJointPassIfBranches = 8,      // the joint pass, on displays of more than one branch only
  kPairLatticePass = 16,         // a branch's target binned by pixel pair (pair_lattice.h), where it pays
  kPairLatticeIfOneBranch = 32,  // the same, on displays of one branch only
  kAllPasses = 63,
};

}  // namespace layerlab
