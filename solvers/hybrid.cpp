// hybrid: the paper's Fig. 2 for any number of branches (multiplicative sets).
// Each outer iteration visits the sets in turn; a set chases the target
// minus the light of the other sets (floored at 0) with `sub_iterations`
// multiplicative updates of each of its layers. A set not yet updated counts
// as emitting its share of the target (its weight over the sum of the
// weights, per channel): for the paper's two equal sets, half the target.
#include <algorithm>
#include <vector>

#include "solvers/multiplicative_update.h"
#include "solvers/solve_loop.h"
#include "systems/view_synthesizer.h"

namespace layerlab {
namespace {

class HybridSolver final : public Solver {
 public:
  SolverReport Solve(const DisplayModel& model, const LightField& target, const SolverOptions& options,
                     Patterns* t) const override {
    SolveLoop loop("hybrid", model, target, options, t);
    if (!loop.Start()) return loop.Finish();
    const LightField& l = loop.target();
    const size_t branches = model.branch_count();
    const size_t n = model.geometry().pixels_per_view() * 3;

    std::array<float, 3> total{0, 0, 0};
    for (size_t b = 0; b < branches; ++b)
      for (int c = 0; c < 3; ++c) total[c] += model.weight(b)[c];
    // After one iteration every set has emitted light of its own.
    std::vector<bool> started(branches, loop.resumed() && loop.iteration() > 0);
    LightField chase(model.geometry());  // what the set being updated should emit

    do {
      for (size_t m = 0; m < branches; ++m) {
        // The other sets stay fixed while this one is updated: their light is computed once.
        const size_t views = model.geometry().view_count();
        thread_local PaddedLayers workspace;
        const ViewSynthesizer synthesizer(model, *t, &workspace);
#pragma omp parallel
        {
          thread_local std::vector<float> other;
          other.resize(n);
#pragma omp for schedule(static)
          for (size_t order = 0; order < views; ++order) {
            const size_t view = synthesizer.ViewInColumnOrder(order);
            const float* lv = l.view(view);
            float* out = chase.view(view);
            std::copy(lv, lv + n, out);
            for (size_t b = 0; b < branches; ++b) {
              if (b == m) continue;
              if (started[b]) {
                synthesizer.Branch(b, view, other.data());
                for (size_t k = 0; k < n; ++k) out[k] -= other[k];
              } else {
                for (size_t k = 0; k < n; ++k) out[k] -= lv[k] * model.weight(b)[k % 3] / total[k % 3];
              }
            }
            for (size_t k = 0; k < n; ++k) out[k] = std::max(out[k], 0.0f);
          }
        }
        BranchTarget target_of_set = [&](size_t view, float*) { return chase.view(view); };
        std::vector<int> order = model.branch_layers(m);
        std::sort(order.begin(), order.end());
        for (int s = 0; s < options.sub_iterations; ++s)
          for (int layer : order) UpdateLayerMultiplicative(model, m, layer, target_of_set, options, t);
        started[m] = true;
      }
    } while (loop.EndIteration());
    return loop.Finish();
  }
};

}  // namespace

SolverType HybridSolverType() {
  return {"hybrid", "the paper's algorithm (Fig. 2): each multiplicative set chases the target minus the others",
          [] { return std::make_unique<HybridSolver>(); }, SolverOptions{}};
}

}  // namespace layerlab
