// hybrid: the paper's Fig. 2 for any number of branches (multiplicative sets).
// Each outer iteration visits the sets in turn; a set chases the target
// minus the light of the other sets (floored at 0) with `sub_iterations`
// multiplicative updates of each of its layers. A set not yet updated counts
// as emitting its share of the target (its weight over the sum of the
// weights, per channel): for the paper's two equal sets, half the target.
#include <algorithm>
#include <optional>
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

    const size_t views = model.geometry().view_count();
    // chase = max(0, target - the light of every set but m).
    auto compute_chase = [&](size_t m) {
      // The other sets stay fixed while this one is updated: their light is computed once.
      thread_local PaddedLayers workspace;
      const ViewSynthesizer synthesizer(model, *t, &workspace);
      std::vector<size_t> others;  // the other sets, if all have emitted light of their own
      for (size_t b = 0; b < branches; ++b)
        if (b != m) others.push_back(b);
      if (!std::all_of(others.begin(), others.end(), [&](size_t b) { return bool(started[b]); })) others.clear();
#pragma omp parallel
      {
        thread_local std::vector<float> other;
        other.resize(n);
#pragma omp for schedule(static)
        for (size_t order = 0; order < views; ++order) {
          const size_t view = synthesizer.ViewInColumnOrder(order);
          const float* lv = l.view(view);
          float* out = chase.view(view);
          if (!others.empty() && synthesizer.Remainder(others, view, lv, out)) continue;
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
    };
    // The next iteration's first chase (set 0's) and this iteration's
    // objective from one pass over the rays, when every set is on the
    // one-tap path; nothing otherwise (the loop then computes the objective).
    auto chase_and_objective = [&]() -> std::optional<double> {
      thread_local PaddedLayers workspace;
      const ViewSynthesizer synthesizer(model, *t, &workspace);
      if (branches < 2 || !synthesizer.AllOneTap()) return std::nullopt;
      std::vector<size_t> others;
      for (size_t b = 1; b < branches; ++b) others.push_back(b);
      std::vector<double> per_view(views);  // summed in view order: the same for any thread count
#pragma omp parallel for schedule(static)
      for (size_t order = 0; order < views; ++order) {
        const size_t view = synthesizer.ViewInColumnOrder(order);
        synthesizer.RemainderAndError(others, view, l.view(view), chase.view(view), &per_view[view]);
      }
      double total_error = 0;
      for (double e : per_view) total_error += e;
      return total_error;
    };

    bool chase_ready = false;  // set 0's chase came with the last iteration's objective
    std::optional<double> objective;
    do {
      for (size_t m = 0; m < branches; ++m) {
        if (!(m == 0 && chase_ready)) compute_chase(m);
        BranchTarget target_of_set = [&](size_t view, float*) { return chase.view(view); };
        std::vector<int> order = model.branch_layers(m);
        std::sort(order.begin(), order.end());
        for (int s = 0; s < options.sub_iterations; ++s)
          for (int layer : order) UpdateLayerMultiplicative(model, m, layer, target_of_set, options, t);
        started[m] = true;
      }
      objective = chase_and_objective();
      chase_ready = objective.has_value();
    } while (loop.EndIteration(objective));
    return loop.Finish();
  }
};

}  // namespace

SolverType HybridSolverType() {
  return {"hybrid", "the paper's algorithm (Fig. 2): each multiplicative set chases the target minus the others",
          [] { return std::make_unique<HybridSolver>(); }, SolverOptions{}};
}

}  // namespace layerlab
