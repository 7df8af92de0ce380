// What the every-layer solvers (joint, quasi-newton, multiplicative's
// depth-by-depth path) read of a pass over the rays: the objective
// ||l - l~||^2 of the patterns it reads and every layer's sums res and den
// (kernels/joint_pass.h defines them): the plain forward model's pass
// (JointPass) and the one through the panels' LC response
// (solvers/response_pass.h) alike.
#pragma once

#include <vector>

#include "layerlab/framework/lightfield.h"
#include "layerlab/systems/display_model.h"

namespace layerlab {

class RayPass {
 public:
  virtual ~RayPass() = default;
  // Returns ||l - l~||^2 of `t`; residual() and denominator() then hold its sums. With `summed` ([layer],
  // nonzero: needed) a pass may leave the other layers' sums unwritten; without `with_objective` it may skip
  // the objective and return 0.
  virtual double Run(const LightField& l, const Patterns& t, const std::vector<char>* summed = nullptr,
                     bool with_objective = true) = 0;
  // [layer][pixel * 3 + channel]
  virtual const std::vector<std::vector<double>>& residual() const = 0;
  virtual const std::vector<std::vector<double>>& denominator() const = 0;
};

}  // namespace layerlab
