#include "layerlab/solvers/display_jacobian.h"

#include <algorithm>
#include <cmath>

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

Patterns DisplayJacobian::Transposed(const Patterns& t, const LightField& v) {
  const LightField& light = Light(t);
  if (v.rgb.size() != light.rgb.size()) throw Error("internal error: a light-field gradient of another geometry");
  Patterns gradient;
  for (const LayerPattern& p : t) gradient.emplace_back(p.cols, p.rows, 0.0f);
  // v scaled by a power of two s to the light's size, so that L - s v keeps v's digits (a v much smaller than
  // L, as a mean loss's gradient over millions of rays is, would otherwise round away); the sums are then
  // divided by s, exactly.
  float v_max = 0, light_max = 0;
#pragma omp parallel for schedule(static) reduction(max : v_max, light_max)
  for (size_t i = 0; i < v.rgb.size(); ++i) {
    v_max = std::max(v_max, std::abs(v.rgb[i]));
    light_max = std::max(light_max, std::abs(light.rgb[i]));
  }
  if (v_max == 0) return gradient;
  const float s = std::ldexp(1.0f, std::ilogb(light_max > 0 ? light_max : 1.0f) - std::ilogb(v_max));
  if (effective_.rgb.size() != light.rgb.size()) effective_ = LightField(light.geometry);
#pragma omp parallel for schedule(static)
  for (size_t i = 0; i < v.rgb.size(); ++i) effective_.rgb[i] = light.rgb[i] - s * v.rgb[i];
  const std::vector<std::vector<double>>& sums = SumsAgainst(effective_).residual();
  const double inverse = 1.0 / s;
  for (size_t k = 0; k < t.size(); ++k)
    for (size_t i = 0; i < gradient[k].rgb.size(); ++i) gradient[k].rgb[i] = static_cast<float>(sums[k][i] * inverse);
  return gradient;
}

}  // namespace layerlab
