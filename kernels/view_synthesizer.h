// The light field of one set of patterns, view by view: branches that take
// the one-tap fast path (one_tap_view.h) read patterns padded once here; the
// others go through the projections.
#pragma once

#include <cstdint>

#include "layerlab/kernels/one_tap_view.h"
#include "layerlab/kernels/solve_workspace.h"
#include "layerlab/systems/display_model.h"

namespace layerlab {

class ViewSynthesizer {
 public:
  // Keeps references to all three; `t` must not change while this is in use.
  // `workspace` (sized with kSynthesisPass for at least the team that calls
  // this) holds the padded patterns and each thread's rows and caches.
  ViewSynthesizer(const DisplayModel& model, const Patterns& t, SolveWorkspace* workspace);

  // out = the whole display's light in one view.
  void View(size_t view, float* out) const;
  // out = branch b's light alone in one view.
  void Branch(size_t b, size_t view, float* out) const;
  // out = max(0, target - the light of `branches`) over one view, row by row,
  // if every one of them is on the one-tap path; false (out untouched) if not.
  bool Remainder(const std::vector<size_t>& branches, size_t view, const float* target, float* out) const;
  // True if every branch is on the one-tap path.
  bool AllOneTap() const { return general_.empty(); }
  // Remainder, and in the same pass the whole display's squared error as
  // SquaredError gives it; false (nothing done) unless every branch is on
  // the one-tap path.
  bool RemainderAndError(const std::vector<size_t>& branches, size_t view, const float* target, float* out,
                         double* error) const;
  // Sum over the rays and channels of one view of (target - light)^2, in
  // double; `target` is that view, [row][col][rgb].
  double SquaredError(size_t view, const float* target) const;

  // The k-th view in view-column order. Each thread keeps the layers
  // resampled for the last view column it synthesized: loops over views that
  // go in this order and hand each thread a run of them (schedule(static))
  // resample each layer about once per view column and thread.
  size_t ViewInColumnOrder(size_t k) const;

 private:
  // out = the light of `branches` (all fast-path) in one view, row by row.
  void OneTapBranches(const std::vector<size_t>& branches, size_t view, float* out) const;
  // row = the light of `branches` in ray row i of one view, [ray][rgb, 0].
  void OneTapRow(const std::vector<size_t>& branches, size_t view, int i, Rgb4* row) const;

  const DisplayModel& model_;
  const Patterns& t_;
  std::vector<size_t> one_tap_, general_;  // branches by path
  SolveWorkspace& workspace_;
  uint64_t id_;  // tells this synthesizer's per-thread caches from an earlier one's
};

}  // namespace layerlab
