#include "systems/one_tap_view.h"

#include "framework/error.h"

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
void AddRowOf(const OneTapView<L>& v, const PaddedLayers& padded, int i, Rgb4 w, Rgb4* row) {
  const Rgb4* rows[L];
  if (!v.Rows(padded, i, rows)) return;
  for (const auto& c : v.columns()) {
    Rgb4 p = w;
    for (int k = 0; k < L; ++k) p *= rows[k][c.pixel[k]];
    row[c.ray] += p;
  }
}

using AnyOneTapView = std::variant<OneTapView<1>, OneTapView<2>, OneTapView<3>, OneTapView<4>>;

template <class... Args>
AnyOneTapView ViewOf(const DisplayModel& model, size_t b, Args... args) {
  static_assert(kMaxOneTapLayers == 4);
  const int* layers = model.branch_layers(b).data();
  switch (model.branch_layers(b).size()) {
    case 1: return OneTapView<1>(model, layers, args...);
    case 2: return OneTapView<2>(model, layers, args...);
    case 3: return OneTapView<3>(model, layers, args...);
    case 4: return OneTapView<4>(model, layers, args...);
  }
  throw Error("branch " + std::to_string(b) + " does not take the one-tap path");
}

Rgb4 WeightOf(const DisplayModel& model, size_t b) {
  const std::array<float, 3>& w = model.weight(b);
  return Rgb4{w[0], w[1], w[2], 0.0f};
}

}  // namespace

OneTapBranchView::OneTapBranchView(const DisplayModel& model, size_t b, const AxisTap* const* row_taps,
                                   const AxisTap* const* col_taps, int ray_cols)
    : view_(ViewOf(model, b, row_taps, col_taps, ray_cols)), weight_(WeightOf(model, b)) {}

void OneTapBranchView::AddRow(const PaddedLayers& padded, int i, Rgb4* row) const {
  std::visit([&](const auto& v) { AddRowOf(v, padded, i, weight_, row); }, view_);
}

void PackRow(const Rgb4* row, int cols, float* out) {
  if (cols <= 0) return;
  // Each 16-byte store spills its padding onto the next ray's red, which the
  // next store overwrites; the last ray is stored exactly, so that rows may be
  // written by different threads in any order.
  for (int j = 0; j + 1 < cols; ++j) std::memcpy(out + j * 3, &row[j], sizeof(Rgb4));
  StoreRgb(row[cols - 1], out + (cols - 1) * 3);
}

}  // namespace layerlab
