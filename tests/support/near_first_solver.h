// A solver that tests register at run time, to show that one file and one
// SolverRegistry::add make a solver that `compare`, the stiff suite and the
// scene reader know: "near-first", the multiplicative update rules of a
// one-branch display visiting the layers from the nearest to the farthest
// (the built-in goes farthest first), every layer once per iteration.
#pragma once

#include <algorithm>
#include <functional>
#include <memory>
#include <string>

#include "layerlab/solvers/multiplicative_update.h"
#include "layerlab/solvers/solve_loop.h"
#include "layerlab/solvers/solver.h"

namespace layerlab::testing {

inline std::string NearFirstUnsuitable(const DisplaySystem& system) {
  return system.branches.size() == 1 ? "" : "needs a display of one branch";
}

class NearFirstSolver final : public Solver {
 public:
  SolverReport Solve(const DisplayModel& model, const LightField& target, const SolverOptions& options,
                     Patterns* t) const override {
    SolveLoop loop("near-first", model, target, options, t);
    if (!loop.Start(NearFirstUnsuitable(model.system()).empty() ? "" : "near-first needs a display of one branch"))
      return loop.Finish();
    const LightField& l = loop.target();
    const BranchTarget whole = [&](size_t view, float*) { return l.view(view); };
    std::vector<int> order = model.branch_layers(0);
    std::sort(order.begin(), order.end(), std::greater<int>());
    do {
      for (int layer : order) UpdateLayerMultiplicative(model, 0, layer, whole, options, t, &loop.workspace());
    } while (loop.EndIteration());
    return loop.Finish();
  }
};

inline SolverType NearFirstSolverType() {
  SolverOptions defaults;
  defaults.iterations = 40;
  SolverType type(
      "near-first", "multiplicative updates of one stack, nearest layer first",
      [] { return std::make_unique<NearFirstSolver>(); }, defaults);
  type.unsuitable = NearFirstUnsuitable;
  type.default_rank = 0;  // never a display's default
  return type;
}

}  // namespace layerlab::testing
