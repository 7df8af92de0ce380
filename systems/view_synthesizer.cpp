#include "systems/view_synthesizer.h"

#include <algorithm>

namespace layerlab {
namespace {

using Double4 = double __attribute__((vector_size(32)));

// sum += (target - light)^2 of one ray (lane 3 ignored). By reference: a
// 32-byte vector passed by value would change the ABI between SSE and AVX builds.
inline void AddSquared(Double4& sum, Rgb4 target, Rgb4 light) {
  target[3] = 0.0f;
  light[3] = 0.0f;
  const Double4 d = __builtin_convertvector(target, Double4) - __builtin_convertvector(light, Double4);
  sum += d * d;
}

}  // namespace

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

double ViewSynthesizer::SquaredError(size_t view, const float* target) const {
  const LightFieldGeometry& g = model_.geometry();
  const size_t n = g.pixels_per_view() * 3;
  if (!general_.empty()) {
    thread_local std::vector<float> light;
    light.resize(n);
    View(view, light.data());
    Double4 sum[2] = {};
    size_t k = 0;
    for (; k + 3 <= n; k += 3) AddSquared(sum[k & 1], LoadRgb(target + k), LoadRgb(light.data() + k));
    return (sum[0][0] + sum[1][0]) + (sum[0][1] + sum[1][1]) + (sum[0][2] + sum[1][2]);
  }
  // Row by row from the padded light: nothing of view size is written.
  std::vector<OneTapBranchView> views;
  for (size_t b : one_tap_) views.emplace_back(model_, b, view);
  thread_local std::vector<Rgb4> row;
  row.resize(g.cols);
  Double4 sum[2] = {};  // two chains of dependent additions, not one
  for (int i = 0; i < g.rows; ++i) {
    std::fill(row.begin(), row.end(), Rgb4{});
    for (const OneTapBranchView& v : views) v.AddRow(padded_, i, row.data());
    const float* l = target + static_cast<size_t>(i) * g.cols * 3;
    int j = 0;
    for (; j + 1 < g.cols; ++j) AddSquared(sum[j & 1], LoadRgbOver(l + j * 3), row[j]);
    AddSquared(sum[j & 1], LoadRgb(l + j * 3), row[j]);
  }
  return (sum[0][0] + sum[1][0]) + (sum[0][1] + sum[1][1]) + (sum[0][2] + sum[1][2]);
}

}  // namespace layerlab
