#include "layerlab/solvers/retinal_pass.h"

#include "layerlab/framework/fixed_order_sum.h"
#include "layerlab/solvers/objective.h"

namespace layerlab {

RetinalPass::RetinalPass(const DisplayModel& model, const LightField& target, const RetinalObjective& objective,
                         const std::vector<LayerDiffraction>* diffraction, bool response)
    : target_(target), objective_(objective), jacobian_(model, diffraction, response), effective_(model.geometry()) {}

namespace {

RetinalMeasures Measures(const RetinalObjective& objective, const LightField& light, const LightField& target,
                         const std::vector<double>& per_state, double f) {
  const double light_field = FixedOrderSquaredDifference(light.rgb.data(), target.rgb.data(), light.rgb.size());
  return {f, light_field, objective.FocalStackPsnr(per_state)};
}

}  // namespace

RetinalMeasures MeasureRetinalObjective(const LightField& target, const RetinalObjective& objective,
                                        const LightField& light) {
  std::vector<double> per_state;
  const double f = objective.Evaluate(light, &per_state);
  return Measures(objective, light, target, per_state, f);
}

double RetinalPass::Run(const Patterns& t) {
  const LightField& light = jacobian_.Light(t);
  std::vector<double> per_state;
  const double f = objective_.EvaluateWithAdjoint(light, &per_state, &effective_);
  last_ = Measures(objective_, light, target_, per_state, f);
  const float inverse_scale = static_cast<float>(1.0 / scale());
#pragma omp parallel for schedule(static)
  for (size_t i = 0; i < effective_.rgb.size(); ++i)
    effective_.rgb[i] = light.rgb[i] - inverse_scale * effective_.rgb[i];
  jacobian_.SumsAgainst(effective_);
  return f / scale();
}

double RetinalPass::Evaluate(const Patterns& t) {
  const LightField& light = jacobian_.Light(t);
  std::vector<double> per_state;
  const double f = objective_.Evaluate(light, &per_state);
  last_ = Measures(objective_, light, target_, per_state, f);
  return f / scale();
}

}  // namespace layerlab
