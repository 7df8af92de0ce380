// The pass of the every-layer solvers through the panels' liquid-crystal
// response (SolverOptions::lc_response; systems/lc_response.h). The display
// shows the frame's time average
//   L(t) = sum_m w_m l~(D x^m),   x^m = R_m t,
// the patterns the panels show at the quadrature's nodes (D: the panels'
// diffraction, or none). For the objective ||L - l||^2 the gradient in t is
// 2 sum_m w_m R_m^T D^T P^T((L - l) o Q^m): a JointPass over x^m against the
// effective target l~(D x^m) - (L - l) sums P^T((L - l) o Q^m), which R_m^T
// maps back to the driven patterns. The denominators are those of each
// instant's own light, sum_m w_m R_m^T D^T P^T(l~(D x^m) o Q^m): quasi-newton
// takes them as its initial scaling only. (A multiplicative step from them
// is no longer Lee and Seung's bound, and any step of one value at a time
// crawls: the response couples a panel's subframes, so the objective's
// Hessian is far from diagonal. On a rank-2 stack of 8 ms panels the joint
// and multiplicative solvers stalled near 2x the error of a solve assuming
// instant panels, where quasi-newton, which learns the coupling, reached a
// fifth of it; the SolverTypes say which solve through the response.)
// A pass costs kResponseNodes x (two syntheses and one joint pass).
#pragma once

#include <optional>
#include <vector>

#include "layerlab/kernels/joint_pass.h"
#include "layerlab/systems/lc_response.h"

namespace layerlab {

// The light field one frame shows through the panels' response `map` (and
// `diffraction`, when given): sum_m w_m l~(D x^m), into *out (of the model's
// geometry); `scratch` (any light field, or null) holds one instant's light.
void ShownLightField(const DisplayModel& model, const ResponseMap& map,
                     const std::vector<LayerDiffraction>* diffraction, LightField* out, LightField* scratch = nullptr,
                     SolveWorkspace* workspace = nullptr);
// Of driven patterns `t`.
LightField ShownLightField(const DisplayModel& model, const Patterns& t,
                           const std::vector<LayerDiffraction>* diffraction = nullptr);

class ResponsePass final : public RayPass {
 public:
  // In the solve's `workspace` (sized with kJointPass and kSynthesisPass) or one of its own; `diffraction` kept
  // by the caller, or null.
  ResponsePass(const DisplayModel& model, SolveWorkspace* workspace,
               const std::vector<LayerDiffraction>* diffraction = nullptr);

  // The frame's light field L(t), kept for SumsOfLight.
  const LightField& Light(const Patterns& t);
  // The sums for the patterns last given to Light against target `l` (returns ||L - l||^2 when asked).
  double SumsOfLight(const LightField& l, const std::vector<char>* summed = nullptr, bool with_objective = true);

  double Run(const LightField& l, const Patterns& t, const std::vector<char>* summed = nullptr,
             bool with_objective = true) override;
  const std::vector<std::vector<double>>& residual() const override { return residual_; }
  const std::vector<std::vector<double>>& denominator() const override { return denominator_; }

 private:
  const DisplayModel& model_;
  SolveWorkspace* workspace_;
  const std::vector<LayerDiffraction>* diffraction_;
  JointPass pass_;  // over one instant's patterns
  const Patterns* driven_ = nullptr;
  std::optional<ResponseMap> map_;
  LightField light_, instant_;  // L(t); one instant's light, then the effective target in place
  Patterns shown_, seen_;       // x^m, D x^m
  std::vector<std::vector<double>> residual_, denominator_;
};

}  // namespace layerlab
