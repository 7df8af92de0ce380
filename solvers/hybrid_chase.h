// The hybrid's chase (paper Fig. 2): what multiplicative set m should emit
// while it is updated, the target minus the light of the other sets, which
// stay fixed meanwhile, floored at 0:
//   chase_m = max(0, l - sum_{b != m} w_b prod_{k in b} P_k t_k).
// A set not yet updated counts as emitting its share of the target (its
// weight over the sum of the weights, per channel): for the paper's two
// equal sets, half the target.
//
// The chase is computed over every view at once (Compute), or, where every
// set is on the one-tap path and the other sets have emitted light of their
// own, view by view inside the pass of the set's first update, which reads
// each view right after it is written (Following).
#pragma once

#include <array>
#include <optional>
#include <vector>

#include "layerlab/framework/lightfield.h"
#include "layerlab/kernels/view_synthesizer.h"
#include "layerlab/solvers/multiplicative_update.h"
#include "layerlab/systems/display_model.h"

namespace layerlab {

class HybridChase {
 public:
  // Allocates the chase (a light field; part of the solve's set-up).
  // `t` is read, never written, and may change between the calls below.
  HybridChase(const DisplayModel& model, const Patterns& t);

  // Before the first call below: the target the sets chase, whether every
  // set has emitted light of its own already (a resumed solve), and the
  // solve's workspace (sized with kSynthesisPass) the synthesizers use.
  void Begin(const LightField& target, bool started, SolveWorkspace* workspace);

  // The chase of set m over every view, from the patterns as they are now.
  void Compute(size_t m);
  // True if set m's chase can come from the pass of its first update (Following).
  bool CanFollow(size_t m) const;
  // What a pass reads when it makes the chase of set m view by view from the
  // patterns as they are now (they must not change during the pass); with
  // `per_view`, the same pass gives each view's squared error of the whole
  // display. Every set must be on the one-tap path.
  BranchTarget Following(size_t m, std::vector<double>* per_view = nullptr);
  // The chase as last computed, for the set's further updates.
  BranchTarget Stored() const;
  const LightField& chase() const { return chase_; }

  // Set m has been updated: from now on it emits light of its own.
  void MarkStarted(size_t m) { started_[m] = true; }
  bool AllOneTap() const { return all_one_tap_; }

 private:
  std::vector<size_t> OthersOf(size_t m) const;
  bool OthersStarted(size_t m) const;

  const DisplayModel& model_;
  const Patterns& t_;
  const LightField* target_ = nullptr;
  LightField chase_;
  std::vector<bool> started_;
  std::array<float, 3> total_weight_{0, 0, 0};
  bool all_one_tap_ = true;
  SolveWorkspace* workspace_ = nullptr;
  std::optional<ViewSynthesizer> following_;  // of the pass in progress
};

}  // namespace layerlab
