#include "systems/view_synthesizer.h"

#include <algorithm>

namespace layerlab {

ViewSynthesizer::ViewSynthesizer(const DisplayModel& model, const Patterns& t, PaddedLayers* workspace)
    : model_(model), t_(t), padded_(*workspace) {
  for (size_t b = 0; b < model.branch_count(); ++b) {
    const bool fast = OneTapBranch(model, b);
    (fast ? one_tap_ : general_).push_back(b);
    if (fast) workspace->Pad(t, model.branch_layers(b));
  }
}

void ViewSynthesizer::OneTapBranches(const std::vector<size_t>& branches, size_t view, float* out) const {
  const LightFieldGeometry& g = model_.geometry();
  std::vector<OneTapBranchView> views;
  for (size_t b : branches) views.emplace_back(model_, b, view);
  thread_local std::vector<Rgb4> row;
  row.resize(g.cols);
  for (int i = 0; i < g.rows; ++i) {
    std::fill(row.begin(), row.end(), Rgb4{});
    for (const OneTapBranchView& v : views) v.AddRow(padded_, i, row.data());
    PackRow(row.data(), g.cols, out + static_cast<size_t>(i) * g.cols * 3);
  }
}

void ViewSynthesizer::View(size_t view, float* out) const {
  const size_t n = model_.geometry().pixels_per_view() * 3;
  if (one_tap_.empty())
    std::fill(out, out + n, 0.0f);
  else
    OneTapBranches(one_tap_, view, out);
  if (general_.empty()) return;
  thread_local std::vector<float> scratch;
  scratch.resize(n);
  for (size_t b : general_) {
    model_.SynthesizeBranchView(b, view, t_, scratch.data());
    for (size_t k = 0; k < n; ++k) out[k] += scratch[k];
  }
}

void ViewSynthesizer::Branch(size_t b, size_t view, float* out) const {
  if (std::find(one_tap_.begin(), one_tap_.end(), b) != one_tap_.end())
    OneTapBranches({b}, view, out);
  else
    model_.SynthesizeBranchView(b, view, t_, out);
}

}  // namespace layerlab
