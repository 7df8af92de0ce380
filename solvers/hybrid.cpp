// hybrid: the paper's Fig. 2 for any number of branches (multiplicative sets).
// Each outer iteration visits the sets in turn: a set's chase (the target
// minus the light of the other sets, solvers/hybrid_chase.h), then
// `sub_iterations` multiplicative updates of each of its layers toward it.
// A set of two layers whose rays are at least twice their pixel pairs
// (systems/pair_lattice.h) bins its chase once and makes the updates after
// the first from the pairs: the same sums, a few pairs per pixel instead of
// every ray.
#include <algorithm>
#include <optional>
#include <vector>

#include "framework/mpi_ranks.h"
#include "solvers/hybrid_chase.h"
#include "solvers/multiplicative_update.h"
#include "solvers/solve_loop.h"

namespace layerlab {
namespace {

std::vector<int> LayersOf(const DisplayModel& model, size_t m) {
  std::vector<int> order = model.branch_layers(m);
  std::sort(order.begin(), order.end());
  return order;
}

class HybridSolver final : public Solver {
 public:
  SolverReport Solve(const DisplayModel& model, const LightField& target, const SolverOptions& options,
                     Patterns* t) const override {
    SolveLoop loop("hybrid", model, target, options, t);
    HybridChase chase(model, *t);  // allocated in the set-up
    if (!loop.Start()) return loop.Finish();
    // After one iteration every set has emitted light of its own.
    SolveWorkspace* workspace = &loop.workspace();
    chase.Begin(loop.target(), loop.resumed() && loop.iteration() > 0, workspace);
    const size_t branches = model.branch_count();
    std::vector<std::optional<PairLattice>> lattices;
    for (size_t m = 0; m < branches; ++m) lattices.push_back(PairLattice::IfItPays(model, m));
    // The pass that gives an iteration's objective also gives set 0's next
    // chase and the sums of its next first update, applied only if there is
    // a next iteration.
    LayerUpdate next_first = KeptLayerUpdate(workspace);
    bool next_first_ready = false;
    std::optional<double> objective;
    do {
      for (size_t m = 0; m < branches; ++m) {
        const std::vector<int> order = LayersOf(model, m);
        // 1. The chase of set m, and with it (where it comes from that pass) the set's first update.
        bool first_done = false;
        if (m == 0 && next_first_ready) {
          ApplyLayerUpdate(next_first, options, t);
          first_done = true;
        } else if (chase.CanFollow(m)) {
          UpdateLayerMultiplicative(model, m, order[0], chase.Following(m), options, t, workspace);
          first_done = true;
        } else {
          chase.Compute(m);
        }
        // 2. The set's layers updated in turn toward its chase, the other sets fixed.
        const BranchTarget stored = chase.Stored();
        const int updates = options.sub_iterations * static_cast<int>(order.size()) - (first_done ? 1 : 0);
        const bool from_pairs = lattices[m] && updates >= 2;  // binning costs about one pass over the rays
        if (from_pairs) lattices[m]->Bin(chase.chase(), &workspace->pair_cells);
        for (int s = 0; s < options.sub_iterations; ++s)
          for (size_t k = 0; k < order.size(); ++k) {
            if (s == 0 && k == 0 && first_done) continue;
            if (from_pairs)
              UpdateLayerFromPairs(model, m, order[k], *lattices[m], workspace->pair_cells, options, t, workspace);
            else
              UpdateLayerMultiplicative(model, m, order[k], stored, options, t, workspace);
          }
        chase.MarkStarted(m);
      }
      // 3. The objective, from the pass that also makes set 0's next chase and first update.
      next_first_ready = false;
      objective.reset();
      if (branches >= 2 && chase.AllOneTap()) {
        // Summed in view order: the same for any thread count.
        std::vector<double> per_view(model.geometry().view_count());
        ComputeLayerUpdate(model, 0, LayersOf(model, 0)[0], chase.Following(0, &per_view), *t, workspace, &next_first);
        double total_error = 0;
        for (double e : per_view) total_error += e;
        objective = SumAcrossRanks(total_error);
        next_first_ready = true;
      }
    } while (loop.EndIteration(objective));
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
