#include "layerlab/systems/display_model.h"

#include <algorithm>
#include <cmath>

#include "layerlab/framework/error.h"

namespace layerlab {

DisplayModel::DisplayModel(const DisplaySystem& system, const LightFieldGeometry& lf, Sampling sampling)
    : system_(system), lf_(lf), sampling_(sampling) {
  for (const VirtualLayer& layer : system.layers) projections_.emplace_back(layer, lf, sampling);
  for (const Branch& b : system.branches)
    for (int c = 0; c < 3; ++c)  // a subframe's branch shown in every subframe of the frame
      white_luminance_ = std::max(white_luminance_, b.backlight_luminance_cd_m2 * b.efficiency[c] * system.subframes);
  for (const Branch& b : system.branches) {
    std::array<float, 3> w{};
    for (int c = 0; c < 3; ++c)
      w[c] = static_cast<float>(b.backlight_luminance_cd_m2 * b.efficiency[c] / white_luminance_);
    weights_.push_back(w);
  }
  pair_lists_ = std::make_shared<PairLists>();
  pair_lists_->made = std::vector<std::once_flag>(system.branches.size());
  pair_lists_->lists.resize(system.branches.size());
}

const MappedPairs* DisplayModel::pair_list(size_t b) const {
  std::call_once(pair_lists_->made[b], [&] {
    std::vector<int> layers = branch_layers(b);
    if (layers.size() != 2) return;
    std::sort(layers.begin(), layers.end());
    const LayerProjection &a = projections_[layers[0]], &p = projections_[layers[1]];
    if (!MappedPairs::Suits(a, p)) return;
    auto list = std::make_unique<const MappedPairs>(layers[0], a, layers[1], p);
    if (list->Pays()) pair_lists_->lists[b] = std::move(list);
  });
  return pair_lists_->lists[b].get();
}

Patterns DisplayModel::UniformPatterns(float value) const {
  Patterns t;
  for (const LayerProjection& p : projections_) t.emplace_back(p.cols(), p.rows(), value);
  return t;
}

void DisplayModel::SynthesizeBranchView(size_t b, size_t view, const Patterns& t, float* out,
                                        std::vector<float>* scratch) const {
  const std::vector<int>& layers = branch_layers(b);
  std::vector<float> own;
  if (!scratch) scratch = &own;
  projections_[layers[0]].Gather(view, t[layers[0]].rgb.data(), out);
  for (size_t k = 1; k < layers.size(); ++k)
    projections_[layers[k]].GatherMultiply(view, t[layers[k]].rgb.data(), out, scratch);
  const std::array<float, 3>& w = weights_[b];
  const size_t n = lf_.pixels_per_view();
  for (size_t ray = 0; ray < n; ++ray)
    for (int c = 0; c < 3; ++c) out[ray * 3 + c] *= w[c];
}

LightFieldGeometry DisplayLightFieldGeometry(const DisplaySystem& system, double origin_diopters) {
  if (system.layers.empty()) throw Error("the display has no layers");
  // The panels' layers: a backlight's emission (elements/backlight.cpp) is lit through them, not an image.
  double near = 0, far = INFINITY;
  const VirtualLayer* farthest = nullptr;
  for (const VirtualLayer& l : system.layers)
    if (!l.panel.emitter) {
      near = std::max(near, l.diopters), far = std::min(far, l.diopters);
      if (!farthest) farthest = &l;
    }
  if (!farthest) throw Error("the display has no panels");
  if (origin_diopters < 0) origin_diopters = 0.5 * (near + far);
  if (!(origin_diopters > 0)) throw Error("the light-field origin plane must be at a finite depth (above 0 D)");
  LightFieldGeometry g;
  g.origin_z_m = 1.0 / origin_diopters;
  g.window_width_m = 2 * g.origin_z_m * std::tan(system.fov_x_rad / 2);
  g.window_height_m = 2 * g.origin_z_m * std::tan(system.fov_y_rad / 2);
  g.window_left_m = -g.window_width_m / 2;
  g.window_top_m = g.window_height_m / 2;
  g.cols = farthest->cols;
  g.rows = farthest->rows;
  g.views_x = system.eye.views_x;
  g.views_y = system.eye.views_y;
  g.eyebox_width_m = system.eye.eyebox_width_m;
  g.eyebox_height_m = system.eye.eyebox_height_m;
  return g;
}

}  // namespace layerlab

namespace layerlab {

std::vector<std::string> TargetGeometryWarnings(const DisplaySystem& system, const LightFieldGeometry& target) {
  const LightFieldGeometry own = DisplayLightFieldGeometry(system);
  auto pair = [](double a, double b, int decimals, const char* unit) {
    return FormatFixed(a, decimals) + " x " + FormatFixed(b, decimals) + unit;
  };
  auto field = [](double left, double width, double z) {  // degrees between the window's edges seen from the pupil
    return (std::atan((left + width) / z) - std::atan(left / z)) * 180 / std::acos(-1.0);
  };
  const double fx = field(target.window_left_m, target.window_width_m, target.origin_z_m);
  const double fy = field(target.window_top_m - target.window_height_m, target.window_height_m, target.origin_z_m);
  const double dx = system.fov_x_rad * 180 / std::acos(-1.0), dy = system.fov_y_rad * 180 / std::acos(-1.0);
  auto differs = [](double a, double b, double tolerance) { return std::abs(a - b) > tolerance * std::abs(b); };
  std::vector<std::string> parts;
  if (target.views_x != own.views_x || target.views_y != own.views_y)
    parts.push_back(pair(target.views_x, target.views_y, 0, " views (the eye's: ") +
                    pair(own.views_x, own.views_y, 0, ")"));
  if (differs(target.eyebox_width_m, own.eyebox_width_m, 1e-6) ||
      differs(target.eyebox_height_m, own.eyebox_height_m, 1e-6))
    parts.push_back("an eyebox of " + pair(target.eyebox_width_m * 1e3, target.eyebox_height_m * 1e3, 2, " mm") +
                    " (the eye's: " + pair(own.eyebox_width_m * 1e3, own.eyebox_height_m * 1e3, 2, " mm)"));
  if (target.cols != own.cols || target.rows != own.rows)
    parts.push_back(pair(target.cols, target.rows, 0, " pixels per view (the farthest layer's: ") +
                    pair(own.cols, own.rows, 0, ")"));
  if (differs(fx, dx, 0.01) || differs(fy, dy, 0.01))
    parts.push_back("a field of " + pair(fx, fy, 2, " deg") + " (the display's: " + pair(dx, dy, 2, " deg)"));
  if (parts.empty()) return {};
  std::string text = "the target light field's geometry differs from the display's: ";
  for (size_t k = 0; k < parts.size(); ++k) text += (k ? ", " : "") + parts[k];
  return {text + "; the layers are sampled at the target's rays (resampled)"};
}

}  // namespace layerlab
