// hybrid: the paper's Fig. 2 for any number of branches (multiplicative
// sets), its outer iterations in solvers/hybrid_iterations.h.
#include <optional>

#include "layerlab/solvers/hybrid_iterations.h"
#include "layerlab/solvers/solve_loop.h"

namespace layerlab {
namespace {

class HybridSolver final : public Solver {
 public:
  SolverReport Solve(const DisplayModel& model, const LightField& target, const SolverOptions& options,
                     Patterns* t) const override {
    SolveLoop loop("hybrid", model, target, options, t);
    HybridIterations hybrid(model, options, t);  // allocated in the set-up
    if (!loop.Start()) return loop.Finish();
    hybrid.Begin(&loop);
    while (loop.EndIteration(hybrid.Iterate(true))) {
    }
    return loop.Finish();
  }
};

}  // namespace

SolverType HybridSolverType() {
  SolverType type(
      "hybrid", "the paper's algorithm (Fig. 2): each multiplicative set chases the target minus the others",
      [] { return std::make_unique<HybridSolver>(); }, SolverOptions{});
  type.default_rank = 1;
  type.memory.light_fields = 1;  // the chase: what the set being updated should emit
  type.memory.passes = kSynthesisPass | kLayerUpdatePass | kPairLatticePass;
  type.options = {SubIterationsKey()};
  return type;
}

}  // namespace layerlab
