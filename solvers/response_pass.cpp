#include "layerlab/solvers/response_pass.h"

#include "layerlab/framework/error.h"
#include "layerlab/framework/fixed_order_sum.h"
#include "layerlab/framework/mpi_ranks.h"
#include "layerlab/kernels/synthesis.h"

namespace layerlab {

namespace {

// x^m into *shown; returns D x^m (in *seen) or x^m.
const Patterns& SeenAt(const ResponseMap& map, int m, const std::vector<LayerDiffraction>* diffraction, Patterns* shown,
                       Patterns* seen) {
  map.Shown(m, shown);
  if (!diffraction || diffraction->empty()) return *shown;
  DiffractPatterns(*diffraction, *shown, seen);
  return *seen;
}

}  // namespace

void ShownLightField(const DisplayModel& model, const ResponseMap& map,
                     const std::vector<LayerDiffraction>* diffraction, LightField* out, LightField* scratch,
                     SolveWorkspace* workspace) {
  LightField own;
  LightField& at = scratch ? *scratch : own;
  if (at.rgb.size() != model.geometry().ray_count() * 3) at = LightField(model.geometry());
  Patterns shown, seen;
  if (out->rgb.size() != model.geometry().ray_count() * 3) *out = LightField(model.geometry());
  std::fill(out->rgb.begin(), out->rgb.end(), 0.0f);
  for (int m = 0; m < map.instants(); ++m) {
    Synthesize(model, SeenAt(map, m, diffraction, &shown, &seen), &at, workspace);
    const float w = static_cast<float>(map.weight(m));
#pragma omp parallel for schedule(static)
    for (size_t r = 0; r < at.rgb.size(); ++r) out->rgb[r] += w * at.rgb[r];
  }
}

LightField ShownLightField(const DisplayModel& model, const Patterns& t,
                           const std::vector<LayerDiffraction>* diffraction) {
  LightField out(model.geometry());
  ShownLightField(model, ResponseMap(model.system(), t), diffraction, &out);
  return out;
}

ResponsePass::ResponsePass(const DisplayModel& model, SolveWorkspace* workspace,
                           const std::vector<LayerDiffraction>* diffraction)
    : model_(model),
      workspace_(workspace),
      diffraction_(diffraction && !diffraction->empty() ? diffraction : nullptr),
      pass_(model, workspace, diffraction_),
      light_(model.geometry()),
      instant_(model.geometry()) {}

const LightField& ResponsePass::Light(const Patterns& t) {
  driven_ = &t;
  map_.emplace(model_.system(), t);
  ShownLightField(model_, *map_, diffraction_, &light_, &instant_, workspace_);
  return light_;
}

double ResponsePass::SumsOfLight(const LightField& l, const std::vector<char>* summed, bool with_objective) {
  if (!map_) throw Error("internal error: the response pass's sums asked before its light");
  const size_t layers = model_.layer_count();
  residual_.resize(layers), denominator_.resize(layers);
  for (size_t k = 0; k < layers; ++k)
    if (!summed || (*summed)[k])
      residual_[k].assign((*driven_)[k].rgb.size(), 0.0), denominator_[k].assign((*driven_)[k].rgb.size(), 0.0);
  for (int m = 0; m < map_->instants(); ++m) {
    Synthesize(model_, SeenAt(*map_, m, diffraction_, &shown_, &seen_), &instant_, workspace_);
#pragma omp parallel for schedule(static)
    for (size_t r = 0; r < instant_.rgb.size(); ++r) instant_.rgb[r] -= light_.rgb[r] - l.rgb[r];
    pass_.Run(instant_, shown_, summed, /*with_objective=*/false);
    map_->AddTransposed(m, map_->weight(m), summed,
                        {{&pass_.residual(), &residual_}, {&pass_.denominator(), &denominator_}});
  }
  if (!with_objective) return 0;
  return SumAcrossRanks(FixedOrderSquaredDifference(light_.rgb.data(), l.rgb.data(), l.rgb.size()));
}

double ResponsePass::Run(const LightField& l, const Patterns& t, const std::vector<char>* summed, bool with_objective) {
  Light(t);
  return SumsOfLight(l, summed, with_objective);
}

}  // namespace layerlab
