#include "systems/one_tap_view.h"

namespace layerlab {

bool OneTapBranch(const DisplayModel& model, size_t b) {
  const std::vector<int>& layers = model.branch_layers(b);
  return !layers.empty() && layers.size() <= static_cast<size_t>(kMaxOneTapLayers) &&
         std::all_of(layers.begin(), layers.end(), [&](int k) { return model.projection(k).one_tap(); });
}

void PaddedLayers::Pad(const Patterns& t, const std::vector<int>& layers) {
  layers_.resize(t.size());
  for (int k : layers) PadRgb(t[k].rgb, &layers_[k]);
}

void PaddedLayers::PadAll(const Patterns& t) {
  layers_.resize(t.size());
  for (size_t k = 0; k < t.size(); ++k) PadRgb(t[k].rgb, &layers_[k]);
}

namespace {

template <int L>
void AddBranchView(const DisplayModel& model, size_t b, size_t view, const PaddedLayers& padded, float* out) {
  const std::array<float, 3>& w = model.weight(b);
  const Rgb4 w4{w[0], w[1], w[2], 0.0f};
  const OneTapView<L> v(model, model.branch_layers(b).data(), view);
  const auto& columns = v.columns();
  const int cols = model.geometry().cols;
  for (int i = 0; i < model.geometry().rows; ++i) {
    const Rgb4* rows[L];
    if (!v.Rows(padded, i, rows)) continue;
    float* row_out = out + static_cast<size_t>(i) * cols * 3;
    auto light = [&](const typename OneTapView<L>::Column& c) {
      Rgb4 p = w4;
      for (int k = 0; k < L; ++k) p *= rows[k][c.pixel[k]];
      return p;
    };
    // Lane 3 of the light is 0: adding it to the next ray's red changes nothing.
    const size_t safe = v.OverreadSafe(i);
    for (size_t e = 0; e < safe; ++e) {
      float* o = row_out + columns[e].ray * 3;
      const Rgb4 sum = LoadRgbOver(o) + light(columns[e]);
      std::memcpy(o, &sum, sizeof sum);
    }
    for (size_t e = safe; e < columns.size(); ++e) {
      float* o = row_out + columns[e].ray * 3;
      StoreRgb(LoadRgb(o) + light(columns[e]), o);
    }
  }
}

}  // namespace

void AddBranchViewOneTap(const DisplayModel& model, size_t b, size_t view, const PaddedLayers& padded, float* out) {
  switch (model.branch_layers(b).size()) {
    case 1: return AddBranchView<1>(model, b, view, padded, out);
    case 2: return AddBranchView<2>(model, b, view, padded, out);
    case 3: return AddBranchView<3>(model, b, view, padded, out);
    case 4: return AddBranchView<4>(model, b, view, padded, out);
  }
}

}  // namespace layerlab
