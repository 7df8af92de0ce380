// multiplicative: the non-negative update rules for a display of one branch
// (a stack of any number of layers), each iteration updating every layer once,
// from the farthest to the nearest.
#include <algorithm>

#include "framework/error.h"
#include "solvers/multiplicative_update.h"
#include "solvers/solve_loop.h"

namespace layerlab {
namespace {

class MultiplicativeSolver final : public Solver {
 public:
  SolverReport Solve(const DisplayModel& model, const LightField& target, const SolverOptions& options,
                     Patterns* t) const override {
    SolveLoop loop("multiplicative", model, target, options, t);
    if (model.branch_count() != 1) {
      loop.Fail("the multiplicative solver needs a display of one branch; this one has " +
                std::to_string(model.branch_count()) + " (use hybrid)");
      return loop.Finish();
    }
    if (!loop.Start()) return loop.Finish();
    const LightField& l = loop.target();
    BranchTarget whole = [&](size_t view, float*) { return l.view(view); };
    std::vector<int> order = model.branch_layers(0);
    std::sort(order.begin(), order.end());
    do {
      for (int layer : order) UpdateLayerMultiplicative(model, 0, layer, whole, options, t);
    } while (loop.EndIteration());
    return loop.Finish();
  }
};

}  // namespace

SolverType MultiplicativeSolverType() {
  SolverOptions defaults;
  defaults.iterations = 90;  // as many updates of each layer as the hybrid's 30 x 3
  return {"multiplicative", "non-negative multiplicative update rules for one stack of any number of layers",
          [] { return std::make_unique<MultiplicativeSolver>(); }, defaults};
}

}  // namespace layerlab
