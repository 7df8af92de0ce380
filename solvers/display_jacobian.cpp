#include "layerlab/solvers/display_jacobian.h"

#include "layerlab/framework/error.h"
#include "layerlab/kernels/synthesis.h"

namespace layerlab {

DisplayJacobian::DisplayJacobian(const DisplayModel& model, const std::vector<LayerDiffraction>* diffraction,
                                 bool response)
    : model_(model), diffraction_(diffraction && !diffraction->empty() ? diffraction : nullptr) {
  if (response)
    response_.emplace(model, nullptr, diffraction_);
  else
    joint_.emplace(model, nullptr, diffraction_), light_ = LightField(model.geometry());
}

const LightField& DisplayJacobian::Light(const Patterns& t) {
  t_ = &t;
  if (response_) return response_->Light(t);
  if (!diffraction_) {
    Synthesize(model_, t, &light_);
  } else {
    DiffractPatterns(*diffraction_, t, &seen_);
    Synthesize(model_, seen_, &light_);
  }
  return light_;
}

const RayPass& DisplayJacobian::SumsAgainst(const LightField& effective) {
  if (!t_) throw Error("internal error: the display's Jacobian asked before its light");
  if (response_) {
    response_->SumsOfLight(effective, nullptr, /*with_objective=*/false);
  } else {
    joint_->Run(effective, *t_);
  }
  return sums();
}

Patterns DisplayJacobianTransposed(DisplayJacobian* jacobian, const Patterns& t, const LightField& v) {
  const LightField& light = jacobian->Light(t);
  if (v.rgb.size() != light.rgb.size()) throw Error("internal error: a light-field gradient of another geometry");
  LightField effective(light.geometry);
#pragma omp parallel for schedule(static)
  for (size_t i = 0; i < v.rgb.size(); ++i) effective.rgb[i] = light.rgb[i] - v.rgb[i];
  const std::vector<std::vector<double>>& sums = jacobian->SumsAgainst(effective).residual();
  Patterns gradient;
  for (size_t k = 0; k < t.size(); ++k) {
    LayerPattern& g = gradient.emplace_back(t[k].cols, t[k].rows, 0.0f);
    for (size_t i = 0; i < g.rgb.size(); ++i) g.rgb[i] = static_cast<float>(sums[k][i]);
  }
  return gradient;
}

}  // namespace layerlab
