#include "layerlab/solvers/hybrid_iterations.h"

#include <algorithm>

#include "layerlab/framework/mpi_ranks.h"
#include "layerlab/solvers/multiplicative_update.h"

namespace layerlab {
namespace {

std::vector<int> LayersOf(const DisplayModel& model, size_t m) {
  std::vector<int> order = model.branch_layers(m);
  std::sort(order.begin(), order.end());
  return order;
}

}  // namespace

HybridIterations::HybridIterations(const DisplayModel& model, const SolverOptions& options, Patterns* t)
    : model_(model), options_(options), t_(t), chase_(model, *t) {}

void HybridIterations::Begin(SolveLoop* loop) {
  workspace_ = &loop->workspace();
  // After one iteration every set has emitted light of its own, and so has every set of a warm start: its
  // chase is then the target less what the others emit from the first iteration on, not its share of it.
  const bool started = (loop->resumed() && loop->iteration() > 0) || options_.initial_patterns != nullptr;
  chase_.Begin(loop->target(), started, workspace_);
  for (size_t m = 0; m < model_.branch_count(); ++m) pairs_.push_back(BranchPairs::IfItPays(model_, m));
  next_first_ = KeptLayerUpdate(workspace_);
}

std::optional<double> HybridIterations::Iterate(bool objective) {
  const size_t branches = model_.branch_count();
  for (size_t m = 0; m < branches; ++m) {
    const std::vector<int> order = LayersOf(model_, m);
    // 1. The chase of set m, and with it (where it comes from that pass) the set's first update.
    bool first_done = false;
    if (m == 0 && next_first_ready_) {
      ApplyLayerUpdate(next_first_, options_, t_);
      first_done = true;
    } else if (chase_.CanFollow(m)) {
      UpdateLayerMultiplicative(model_, m, order[0], chase_.Following(m), options_, t_, workspace_);
      first_done = true;
    } else {
      chase_.Compute(m);
    }
    // 2. The set's layers updated in turn toward its chase, the other sets fixed.
    const BranchTarget stored = chase_.Stored();
    const int updates = options_.sub_iterations * static_cast<int>(order.size()) - (first_done ? 1 : 0);
    const bool from_pairs = pairs_[m] && updates >= 2;  // binning costs about one pass over the rays
    if (from_pairs) pairs_[m]->Bin(chase_.chase(), workspace_);
    for (int s = 0; s < options_.sub_iterations; ++s)
      for (size_t k = 0; k < order.size(); ++k) {
        if (s == 0 && k == 0 && first_done) continue;
        if (from_pairs)
          UpdateLayerFromPairs(model_, m, order[k], *pairs_[m], options_, t_, workspace_);
        else
          UpdateLayerMultiplicative(model_, m, order[k], stored, options_, t_, workspace_);
      }
    chase_.MarkStarted(m);
  }
  // 3. The objective, from the pass that also makes set 0's next chase and first update.
  next_first_ready_ = false;
  if (!objective || branches < 2 || !chase_.AllOneTap()) return std::nullopt;
  // Summed in view order: the same for any thread count.
  std::vector<double> per_view(model_.geometry().view_count());
  ComputeLayerUpdate(model_, {0, LayersOf(model_, 0)[0]}, chase_.Following(0, &per_view), *t_, workspace_,
                     &next_first_);
  double total_error = 0;
  for (double e : per_view) total_error += e;
  next_first_ready_ = true;
  return SumAcrossRanks(total_error);
}

}  // namespace layerlab
