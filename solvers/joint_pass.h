// One pass over the rays for the solvers that move every layer at once
// (joint, quasi-newton). For the whole objective ||l - l~||^2 with
// l~ = sum_b w_b prod_{k in b} P_k t_k it sums, for every layer a of branch b,
//   num_a = P_a^T(l o Q_a),  den_a = P_a^T(l~ o Q_a),   Q_a = w_b prod_{k in b, k != a} P_k t_k,
// so the gradient is 2 (den_a - num_a), and returns ||l - l~||^2 of the
// patterns it reads.
#pragma once

#include <vector>

#include "framework/lightfield.h"
#include "systems/display_model.h"

namespace layerlab {

class JointPass {
 public:
  explicit JointPass(const DisplayModel& model);

  // Returns ||l - l~||^2 of `t`; numerator() and denominator() then hold its sums.
  double Run(const LightField& l, const Patterns& t);
  // [layer][pixel * 3 + channel]
  const std::vector<std::vector<double>>& numerator() const { return num_; }
  const std::vector<std::vector<double>>& denominator() const { return den_; }

 private:
  struct PassSums;
  void ViewOneTap(const float* target, const Patterns& t, size_t view, PassSums* sums) const;
  void ViewGeneral(const float* target, const Patterns& t, size_t view, PassSums* sums) const;

  const DisplayModel& model_;
  std::vector<int> branch_of_;
  std::vector<int> members_, branch_start_;  // branch b's layers: members_[branch_start_[b] .. branch_start_[b + 1])
  std::vector<float> weights_;               // [branch][channel]
  bool one_tap_ = true;
  bool column_pass_ = false;  // every branch on the one-tap path: JointColumnPass
  // Kept between passes (fresh megabytes would be faulted in each time).
  std::vector<std::vector<double>> num_, den_;
};

}  // namespace layerlab
