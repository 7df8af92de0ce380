// The pass of the every-layer solvers (joint, quasi-newton) under the
// retinal objective (solvers/retinal_objective.h). With L = L(t) the
// display's light field and m = M (L - l) / s, s = RetinalObjective::Bound(),
// a JointPass against the effective target L - m sums
//   res_a = P_a^T((L - (L - m)) o Q_a) = P_a^T(m o Q_a),  den_a = P_a^T(L o Q_a),
// so 2 res_a is the gradient of f / s, f the
// retinal objective; the solvers read those sums as they read the
// light-field pass's. Since M / s <= I, a step safe for the light-field
// objective (the joint solver's multiplicative step, quasi-newton's initial
// scaling) is safe for f / s.
#pragma once

#include <vector>

#include "layerlab/solvers/display_jacobian.h"
#include "layerlab/solvers/retinal_objective.h"

namespace layerlab {

// What the last evaluation measured.
struct RetinalMeasures {
  double objective = 0;              // f, the retinal objective
  double light_field_objective = 0;  // ||L - l||^2
  double focal_stack_psnr_db = 0;    // mean over states
};

// The measures of the display's light field `light` against `target`.
RetinalMeasures MeasureRetinalObjective(const LightField& target, const RetinalObjective& objective,
                                        const LightField& light);

class RetinalPass {
 public:
  // With `diffraction` (kept by the caller) the display's light field is L(D t) (kernels/joint_pass.h); with
  // `response`, the frame's time average through the panels' LC response (solvers/response_pass.h), whose
  // pass takes the same effective target.
  RetinalPass(const DisplayModel& model, const LightField& target, const RetinalObjective& objective,
              const std::vector<LayerDiffraction>* diffraction = nullptr, bool response = false);

  // f(t) / s; residual() and denominator() then hold the sums above.
  double Run(const Patterns& t);
  // f(t) / s alone (no gradient).
  double Evaluate(const Patterns& t);
  const RayPass& sums() const { return jacobian_.sums(); }
  double scale() const { return objective_.Bound(); }
  const RetinalMeasures& last() const { return last_; }

 private:
  const LightField& target_;
  const RetinalObjective& objective_;
  DisplayJacobian jacobian_;
  LightField effective_;  // M (L - l), then L - m
  RetinalMeasures last_;
};

}  // namespace layerlab
