#include "systems/view_synthesizer.h"

namespace layerlab {

ViewSynthesizer::ViewSynthesizer(const DisplayModel& model, const Patterns& t) : model_(model), t_(t) {
  for (size_t b = 0; b < model.branch_count(); ++b) {
    one_tap_.push_back(OneTapBranch(model, b));
    if (one_tap_.back()) padded_.Pad(t, model.branch_layers(b));
  }
}

void ViewSynthesizer::AddBranch(size_t b, size_t view, float* out, float* scratch) const {
  if (one_tap_[b]) return AddBranchViewOneTap(model_, b, view, padded_, out);
  model_.SynthesizeBranchView(b, view, t_, scratch);
  const size_t n = model_.geometry().pixels_per_view() * 3;
  for (size_t k = 0; k < n; ++k) out[k] += scratch[k];
}

void ViewSynthesizer::View(size_t view, float* out, float* scratch) const {
  std::fill(out, out + model_.geometry().pixels_per_view() * 3, 0.0f);
  for (size_t b = 0; b < model_.branch_count(); ++b) AddBranch(b, view, out, scratch);
}

void ViewSynthesizer::Branch(size_t b, size_t view, float* out) const {
  if (!one_tap_[b]) return model_.SynthesizeBranchView(b, view, t_, out);
  std::fill(out, out + model_.geometry().pixels_per_view() * 3, 0.0f);
  AddBranchViewOneTap(model_, b, view, padded_, out);
}

}  // namespace layerlab
