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
    LightField chase(model.geometry());  // what the set being updated should emit; allocated in the set-up
    if (!loop.Start()) return loop.Finish();
    const LightField& l = loop.target();
    const size_t branches = model.branch_count();
    const size_t n = model.geometry().pixels_per_view() * 3;

    std::array<float, 3> total{0, 0, 0};
    for (size_t b = 0; b < branches; ++b)
      for (int c = 0; c < 3; ++c) total[c] += model.weight(b)[c];
    // After one iteration every set has emitted light of its own.
    std::vector<bool> started(branches, loop.resumed() && loop.iteration() > 0);

    const size_t views = model.geometry().view_count();
    auto others_of = [&](size_t m) {
      std::vector<size_t> others;
      for (size_t b = 0; b < branches; ++b)
        if (b != m) others.push_back(b);
      return others;
    };
    // chase = max(0, target - the light of every set but m).
    auto compute_chase = [&](size_t m) {
      // The other sets stay fixed while this one is updated: their light is computed once.
      thread_local PaddedLayers workspace;
      const ViewSynthesizer synthesizer(model, *t, &workspace);
      std::vector<size_t> others = others_of(m);  // the other sets, if all have emitted light of their own
      if (!std::all_of(others.begin(), others.end(), [&](size_t b) { return bool(started[b]); })) others.clear();
      std::array<float, 3> unstarted_share_left{1, 1, 1};  // 1 - the unstarted sets' shares
      for (size_t b = 0; b < branches; ++b)
        if (b != m && !started[b])
          for (int c = 0; c < 3; ++c) unstarted_share_left[c] -= model.weight(b)[c] / total[c];
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
          // The sets not yet started take their shares of the target at once.
          for (size_t k = 0; k < n; k += 3)
            for (int c = 0; c < 3; ++c) out[k + c] = lv[k + c] * unstarted_share_left[c];
          for (size_t b = 0; b < branches; ++b) {
            if (b == m || !started[b]) continue;
            synthesizer.Branch(b, view, other.data());
            for (size_t k = 0; k < n; ++k) out[k] -= other[k];
          }
          for (size_t k = 0; k < n; ++k) out[k] = std::max(out[k], 0.0f);
        }
      }
    };
    // Where every set is on the one-tap path, a set's chase is computed view
    // by view inside the pass of its first update (the update reads each
    // view right after it is written), and the pass that gives an
    // iteration's objective also gives set 0's next chase and the sums of
    // its next first update, applied only if there is a next iteration.
    auto layers_of = [&](size_t m) {
      std::vector<int> order = model.branch_layers(m);
      std::sort(order.begin(), order.end());
      return order;
    };
    bool all_one_tap = true;
    for (size_t b = 0; b < branches; ++b) all_one_tap = all_one_tap && OneTapBranch(model, b);
    BranchTarget stored_chase = [&](size_t view, float*) { return chase.view(view); };
    LayerUpdate next_first;  // set 0's first update of the next iteration
    bool next_first_ready = false;
    std::optional<double> objective;
    do {
      for (size_t m = 0; m < branches; ++m) {
        const std::vector<int> order = layers_of(m);
        const std::vector<size_t> others = others_of(m);
        const bool others_started = std::all_of(others.begin(), others.end(), [&](size_t b) { return bool(started[b]); });
        bool first_done = false;
        if (m == 0 && next_first_ready) {
          ApplyLayerUpdate(next_first, options, t);
          first_done = true;
        } else if (all_one_tap && others_started && !others.empty()) {
          thread_local PaddedLayers workspace;
          const ViewSynthesizer synthesizer(model, *t, &workspace);
          BranchTarget chase_on_the_way = [&](size_t view, float*) {
            synthesizer.Remainder(others, view, l.view(view), chase.view(view));
            return static_cast<const float*>(chase.view(view));
          };
          UpdateLayerMultiplicative(model, m, order[0], chase_on_the_way, options, t);
          first_done = true;
        } else {
          compute_chase(m);
        }
        for (int s = 0; s < options.sub_iterations; ++s)
          for (size_t k = 0; k < order.size(); ++k)
            if (!(s == 0 && k == 0 && first_done)) UpdateLayerMultiplicative(model, m, order[k], stored_chase, options, t);
        started[m] = true;
      }
      next_first_ready = false;
      objective.reset();
      if (branches >= 2 && all_one_tap) {
        thread_local PaddedLayers workspace;
        const ViewSynthesizer synthesizer(model, *t, &workspace);
        const std::vector<size_t> others = others_of(0);
        std::vector<double> per_view(views);  // summed in view order: the same for any thread count
        BranchTarget chase_and_error = [&](size_t view, float*) {
          synthesizer.RemainderAndError(others, view, l.view(view), chase.view(view), &per_view[view]);
          return static_cast<const float*>(chase.view(view));
        };
        ComputeLayerUpdate(model, 0, layers_of(0)[0], chase_and_error, *t, &next_first);
        double total_error = 0;
        for (double e : per_view) total_error += e;
        objective = total_error;
        next_first_ready = true;
      }
    } while (loop.EndIteration(objective));
    return loop.Finish();
  }
};

}  // namespace

SolverType HybridSolverType() {
  SolverType type("hybrid",
                  "the paper's algorithm (Fig. 2): each multiplicative set chases the target minus the others",
                  [] { return std::make_unique<HybridSolver>(); }, SolverOptions{});
  type.default_rank = 1;
  type.memory.light_fields = 1;  // the chase: what the set being updated should emit
  type.options = {SubIterationsKey()};
  return type;
}

}  // namespace layerlab
