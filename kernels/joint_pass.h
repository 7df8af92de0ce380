// One pass over the rays for the solvers that move every layer at once
// (joint, quasi-newton). For the whole objective ||l - l~||^2 with
// l~ = sum_b w_b prod_{k in b} P_k t_k it sums, for every layer a of branch b,
//   res_a = P_a^T((l~ - l) o Q_a),  den_a = P_a^T(l~ o Q_a),   Q_a = w_b prod_{k in b, k != a} P_k t_k,
// so the gradient is 2 res_a and the multiplicative update's ratio
// (den_a - res_a) / den_a, and returns ||l - l~||^2 of the patterns it reads.
// The residual is summed itself: summing P_a^T(l o Q_a) instead and taking
// den_a minus it loses the gradient in float rounding near a solution (the
// two agree to five digits at 50 dB; quasi-newton stopped there).
#pragma once

#include <memory>
#include <vector>

#include "layerlab/framework/lightfield.h"
#include "layerlab/kernels/ray_pass.h"
#include "layerlab/kernels/solve_workspace.h"
#include "layerlab/systems/display_model.h"
#include "layerlab/systems/panel_diffraction.h"

namespace layerlab {

class JointPass final : public RayPass {
 public:
  // In the solve's `workspace` (sized with kJointPass), or without one in a
  // workspace of its own for the thread count of now.
  // With `diffraction` (kept by the caller) the display is seen through its panels' diffraction D
  // (systems/panel_diffraction.h): the pass reads the patterns D t, and the sums, made over D t's pixels, are
  // mapped back to t's by D^T (the gradient's chain rule; for the multiplicative update the convolutive
  // Lee-Seung step, D being non-negative).
  explicit JointPass(const DisplayModel& model, SolveWorkspace* workspace = nullptr,
                     const std::vector<LayerDiffraction>* diffraction = nullptr);

  // Returns ||l - l~||^2 of `t`; residual() and denominator() then hold its
  // sums. With `summed` ([layer], nonzero: needed; joint_column_pass.h) the
  // one-tap path makes only those layers' sums and leaves the others
  // unwritten; the general path makes all. Without `with_objective` the one-tap
  // path does not compute it and returns 0.
  double Run(const LightField& l, const Patterns& t, const std::vector<char>* summed = nullptr,
             bool with_objective = true) override;
  // [layer][pixel * 3 + channel]
  const std::vector<std::vector<double>>& residual() const override { return workspace_->joint_residual; }
  const std::vector<std::vector<double>>& denominator() const override { return workspace_->joint_den; }

 private:
  double RunOn(const LightField& l, const Patterns& t, const std::vector<char>* summed, bool with_objective);
  // Per thread: the float sums of every layer (ThreadWorkspace::num holds res, den), and the view's objective.
  void ViewOneTap(const float* target, const Patterns& t, size_t view, ThreadWorkspace* sums, double* error) const;
  void ViewGeneral(const float* target, const Patterns& t, size_t view, ThreadWorkspace* sums, double* error) const;

  const DisplayModel& model_;
  std::vector<int> branch_of_;
  std::vector<int> members_, branch_start_;  // branch b's layers: members_[branch_start_[b] .. branch_start_[b + 1])
  std::vector<float> weights_;               // [branch][channel]
  bool one_tap_ = true;
  bool column_pass_ = false;  // every branch on the one-tap path: JointColumnPass
  std::unique_ptr<SolveWorkspace> own_;
  SolveWorkspace* workspace_;
  const std::vector<LayerDiffraction>* diffraction_ = nullptr;  // null: none
  Patterns seen_;                                               // D t
};

}  // namespace layerlab
