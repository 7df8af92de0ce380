#include "layerlab/solvers/hybrid_chase.h"

#include <algorithm>

namespace layerlab {

HybridChase::HybridChase(const DisplayModel& model, const Patterns& t)
    : model_(model), t_(t), chase_(model.geometry()), started_(model.branch_count(), false) {
  for (size_t b = 0; b < model.branch_count(); ++b) {
    for (int c = 0; c < 3; ++c) total_weight_[c] += model.weight(b)[c];
    all_one_tap_ = all_one_tap_ && OneTapBranch(model, b);
  }
}

void HybridChase::Begin(const LightField& target, bool started, SolveWorkspace* workspace) {
  target_ = &target;
  workspace_ = workspace;
  std::fill(started_.begin(), started_.end(), started);
}

std::vector<size_t> HybridChase::OthersOf(size_t m) const {
  std::vector<size_t> others;
  for (size_t b = 0; b < model_.branch_count(); ++b)
    if (b != m) others.push_back(b);
  return others;
}

bool HybridChase::OthersStarted(size_t m) const {
  for (size_t b = 0; b < model_.branch_count(); ++b)
    if (b != m && !started_[b]) return false;
  return true;
}

void HybridChase::Compute(size_t m) {
  const LightField& l = *target_;
  const size_t branches = model_.branch_count();
  const size_t n = model_.geometry().pixels_per_view() * 3;
  const size_t views = model_.geometry().view_count();
  const ViewSynthesizer synthesizer(model_, t_, workspace_);
  std::vector<size_t> others = OthersOf(m);  // the other sets, if all have emitted light of their own
  if (!OthersStarted(m)) others.clear();
  std::array<float, 3> unstarted_share_left{1, 1, 1};  // 1 - the unstarted sets' shares
  for (size_t b = 0; b < branches; ++b)
    if (b != m && !started_[b])
      for (int c = 0; c < 3; ++c) unstarted_share_left[c] -= model_.weight(b)[c] / total_weight_[c];
#pragma omp parallel
  {
    std::vector<float>& other = workspace_->thread().branch;
    other.resize(n);
#pragma omp for schedule(static)
    for (size_t order = 0; order < views; ++order) {
      const size_t view = synthesizer.ViewInColumnOrder(order);
      const float* lv = l.view(view);
      float* out = chase_.view(view);
      if (!others.empty() && synthesizer.Remainder(others, view, lv, out)) continue;
      // The sets not yet started take their shares of the target at once.
      for (size_t k = 0; k < n; k += 3)
        for (int c = 0; c < 3; ++c) out[k + c] = lv[k + c] * unstarted_share_left[c];
      for (size_t b = 0; b < branches; ++b) {
        if (b == m || !started_[b]) continue;
        synthesizer.Branch(b, view, other.data());
        for (size_t k = 0; k < n; ++k) out[k] -= other[k];
      }
      for (size_t k = 0; k < n; ++k) out[k] = std::max(out[k], 0.0f);
    }
  }
}

bool HybridChase::CanFollow(size_t m) const { return all_one_tap_ && model_.branch_count() > 1 && OthersStarted(m); }

BranchTarget HybridChase::Following(size_t m, std::vector<double>* per_view) {
  following_.emplace(model_, t_, workspace_);
  const std::vector<size_t> others = OthersOf(m);
  if (per_view)
    return [this, others, per_view](size_t view, float*) {
      following_->RemainderAndError(others, view, target_->view(view), chase_.view(view), &(*per_view)[view]);
      return static_cast<const float*>(chase_.view(view));
    };
  return [this, others](size_t view, float*) {
    following_->Remainder(others, view, target_->view(view), chase_.view(view));
    return static_cast<const float*>(chase_.view(view));
  };
}

BranchTarget HybridChase::Stored() const {
  return [this](size_t view, float*) { return chase_.view(view); };
}

}  // namespace layerlab
