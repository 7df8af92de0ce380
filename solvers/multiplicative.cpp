// multiplicative: the non-negative update rules for a display of one branch
// (a stack of any number of layers), each iteration updating every layer once,
// from the farthest to the nearest.
#include <algorithm>
#include <optional>

#include "framework/error.h"
#include "solvers/multiplicative_update.h"
#include "solvers/solve_loop.h"

namespace layerlab {
namespace {

std::string Unsuitable(const DisplaySystem& system) {
  if (system.branches.size() == 1) return "";
  return "needs a display of one branch; this one has " + std::to_string(system.branches.size()) + " (use hybrid)";
}

class MultiplicativeSolver final : public Solver {
 public:
  SolverReport Solve(const DisplayModel& model, const LightField& target, const SolverOptions& options,
                     Patterns* t) const override {
    SolveLoop loop("multiplicative", model, target, options, t);
    const std::string why = Unsuitable(model.system());
    if (!loop.Start(why.empty() ? why : "the multiplicative solver " + why)) return loop.Finish();
    const LightField& l = loop.target();
    BranchTarget whole = [&](size_t view, float*) { return l.view(view); };
    std::vector<int> order = model.branch_layers(0);
    std::sort(order.begin(), order.end());
    // The pass that gives an iteration's objective also gives the sums of the
    // next iteration's first update (both read the same patterns), which is
    // applied only if there is a next iteration.
    LayerUpdate first;
    ComputeLayerUpdate(model, 0, order[0], whole, *t, &first);
    std::optional<double> objective;
    do {
      ApplyLayerUpdate(first, options, t);
      for (size_t k = 1; k < order.size(); ++k) UpdateLayerMultiplicative(model, 0, order[k], whole, options, t);
      double error = 0;
      const bool fused = ComputeLayerUpdate(model, 0, order[0], whole, *t, &first, &error);
      objective = fused ? std::optional<double>(error) : std::nullopt;
    } while (loop.EndIteration(objective));
    return loop.Finish();
  }
};

}  // namespace

SolverType MultiplicativeSolverType() {
  SolverOptions defaults;
  defaults.iterations = 90;  // as many updates of each layer as the hybrid's 30 x 3
  SolverType type(
      "multiplicative", "non-negative multiplicative update rules for one stack of any number of layers",
      [] { return std::make_unique<MultiplicativeSolver>(); }, defaults);
  type.unsuitable = Unsuitable;
  type.default_rank = 3;
  return type;
}

}  // namespace layerlab
