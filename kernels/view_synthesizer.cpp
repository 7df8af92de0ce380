#include "layerlab/kernels/view_synthesizer.h"

#include <algorithm>
#include <atomic>

namespace layerlab {
namespace {

std::atomic<uint64_t> next_id{1};

}  // namespace

ViewSynthesizer::ViewSynthesizer(const DisplayModel& model, const Patterns& t, SolveWorkspace* workspace)
    : model_(model), t_(t), workspace_(*workspace), id_(next_id++) {
  for (size_t b = 0; b < model.branch_count(); ++b) {
    const bool fast = OneTapBranch(model, b);
    (fast ? one_tap_ : general_).push_back(b);
    if (fast) workspace->padded.Pad(t, model.branch_layers(b));
  }
}

size_t ViewSynthesizer::ViewInColumnOrder(size_t k) const {
  const LightFieldGeometry& g = model_.geometry();
  return g.view_index(static_cast<int>(k % g.views_y), static_cast<int>(k / g.views_y));
}

void ViewSynthesizer::OneTapRow(const std::vector<size_t>& branches, size_t view, int i, Rgb4* row) const {
  const LightFieldGeometry& g = model_.geometry();
  // This thread's one-tap layers resampled to the rays' columns of one view
  // column: within a view column a layer's column depends on the ray's
  // column alone. Rebuilt when the thread moves to another view column or
  // another synthesizer.
  ThreadWorkspace& cache = workspace_.thread();
  const int vc = static_cast<int>(view % g.views_x);
  if (cache.cache_owner != id_ || cache.cache_vc != vc) {
    cache.cache_owner = id_, cache.cache_vc = vc;
    for (size_t b : one_tap_)
      for (int k : model_.branch_layers(b)) {
        const LayerProjection& P = model_.projection(k);  // any view of the column may ask next
        ResampleToRayColumns(P, workspace_.padded.pixels(k), vc, g.cols, RowsRead(P, g, 0, g.views_y), &cache.cache[k]);
      }
  }
  std::fill(row, row + g.cols, Rgb4{});
  for (size_t b : branches) {
    const std::vector<int>& layers = model_.branch_layers(b);
    const Rgb4* rows[kMaxOneTapLayers];
    bool reached = true;
    for (size_t k = 0; k < layers.size() && reached; ++k) {
      const int32_t r = model_.projection(layers[k]).row_taps(view)[i].i0;
      reached = r >= 0;
      if (reached) rows[k] = cache.cache[layers[k]].data() + static_cast<size_t>(r) * g.cols;
    }
    if (!reached) continue;
    const std::array<float, 3>& w = model_.weight(b);
    const Rgb4 w4{w[0], w[1], w[2], 0.0f};
    AddBranchLightRow({rows, static_cast<int>(layers.size()), w4, g.cols}, row);
  }
}

void ViewSynthesizer::OneTapBranches(const std::vector<size_t>& branches, size_t view, float* out) const {
  const LightFieldGeometry& g = model_.geometry();
  std::vector<Rgb4>& row = workspace_.thread().row;
  row.resize(g.cols);
  for (int i = 0; i < g.rows; ++i) {
    OneTapRow(branches, view, i, row.data());
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
  ThreadWorkspace& w = workspace_.thread();
  std::vector<float>& scratch = w.branch;
  scratch.resize(n);
  for (size_t b : general_) {
    model_.SynthesizeBranchView(b, view, t_, scratch.data(), &w.gathered);
    for (size_t k = 0; k < n; ++k) out[k] += scratch[k];
  }
}

void ViewSynthesizer::Branch(size_t b, size_t view, float* out) const {
  if (std::find(one_tap_.begin(), one_tap_.end(), b) != one_tap_.end())
    OneTapBranches({b}, view, out);
  else
    model_.SynthesizeBranchView(b, view, t_, out, &workspace_.thread().gathered);
}

bool ViewSynthesizer::Remainder(const std::vector<size_t>& branches, size_t view, const float* target,
                                float* out) const {
  for (size_t b : branches)
    if (std::find(one_tap_.begin(), one_tap_.end(), b) == one_tap_.end()) return false;
  const LightFieldGeometry& g = model_.geometry();
  std::vector<Rgb4>& row = workspace_.thread().row;
  row.resize(g.cols);
  for (int i = 0; i < g.rows; ++i) {
    OneTapRow(branches, view, i, row.data());
    const size_t start = static_cast<size_t>(i) * g.cols * 3;
    RemainderRow(target + start, row.data(), g.cols, out + start);
  }
  return true;
}

bool ViewSynthesizer::RemainderAndError(const std::vector<size_t>& branches, size_t view, const float* target,
                                        float* out, double* error) const {
  if (!general_.empty()) return false;
  std::vector<size_t> rest;
  for (size_t b : one_tap_)
    if (std::find(branches.begin(), branches.end(), b) == branches.end()) rest.push_back(b);
  const LightFieldGeometry& g = model_.geometry();
  ThreadWorkspace& w = workspace_.thread();
  std::vector<Rgb4>&light = w.row, &rest_light = w.rest_row;
  light.resize(g.cols), rest_light.resize(g.cols);
  double sum = 0;
  for (int i = 0; i < g.rows; ++i) {
    OneTapRow(branches, view, i, light.data());
    OneTapRow(rest, view, i, rest_light.data());
    const size_t start = static_cast<size_t>(i) * g.cols * 3;
    RemainderRow(target + start, light.data(), g.cols, out + start);
    for (int j = 0; j < g.cols; ++j) rest_light[j] += light[j];  // now the whole display's
    sum += SquaredErrorRow(target + start, rest_light.data(), g.cols, i == g.rows - 1);
  }
  *error = sum;
  return true;
}

double ViewSynthesizer::SquaredError(size_t view, const float* target) const {
  const LightFieldGeometry& g = model_.geometry();
  const size_t n = g.pixels_per_view() * 3;
  if (!general_.empty()) {
    std::vector<float>& light = workspace_.thread().synthesized;
    light.resize(n);
    View(view, light.data());
    double sum = 0;
    for (size_t k = 0; k < n; ++k) {
      const double d = double(target[k]) - light[k];
      sum += d * d;
    }
    return sum;
  }
  // Row by row: nothing of view size is written.
  std::vector<Rgb4>& row = workspace_.thread().row;
  row.resize(g.cols);
  double sum = 0;
  for (int i = 0; i < g.rows; ++i) {
    OneTapRow(one_tap_, view, i, row.data());
    sum += SquaredErrorRow(target + static_cast<size_t>(i) * g.cols * 3, row.data(), g.cols, i == g.rows - 1);
  }
  return sum;
}

}  // namespace layerlab
