// The display's forward model L(t) and its Jacobian's transpose, for any
// objective of the display's light field: the retinal objective
// (solvers/retinal_pass.h) and a caller's own loss (Python's layerlab.torch).
//
//   L(t) = l~(D t)                          the light field shown (kernels/synthesis.h)
//   L(t) = sum_m w_m l~(D R_m t)            through the panels' LC response (solvers/response_pass.h)
//
// with D the panels' diffraction (systems/panel_diffraction.h; none when no
// panel diffracts) and time-multiplexed subframes as the model's branches.
// J(t)^T v, the patterns' gradient of <v, L(t)>, comes from the light-field
// pass run against the effective target L - v: its residual sums are
// P^T((L - (L - v)) o Q) = P^T(v o Q), mapped back through D^T and R_m^T.
// Forming L - v rounds once in float: Transposed scales v by a power of two to
// the light's size first, so that the rounding is relative to v, not to L.
#pragma once

#include <optional>
#include <vector>

#include "layerlab/kernels/joint_pass.h"
#include "layerlab/solvers/response_pass.h"

namespace layerlab {

class DisplayJacobian {
 public:
  // `diffraction` (kept by the caller) or null; `response`: through the panels' LC response.
  DisplayJacobian(const DisplayModel& model, const std::vector<LayerDiffraction>* diffraction, bool response);

  // L(t), kept until the next call; `t` must outlive the calls of SumsAgainst that follow.
  const LightField& Light(const Patterns& t);
  // The sums of the pass against `effective` = L - v for the patterns last given to Light: residual() is
  // J^T v ([layer][pixel * 3 + channel], in double).
  const RayPass& SumsAgainst(const LightField& effective);
  // The pass whose sums SumsAgainst makes (the same object before and after).
  const RayPass& sums() const { return response_ ? static_cast<const RayPass&>(*response_) : *joint_; }
  // J(t)^T v at once: the patterns' gradient of <v, L(t)>, as float patterns of t's shapes (L - s v formed in
  // a buffer kept between calls, s a power of two that brings v to the light's size; zero for v = 0).
  Patterns Transposed(const Patterns& t, const LightField& v);
  // Forgets the patterns last given to Light (a caller that only wanted the light, and whose t is gone).
  void Forget() { t_ = nullptr; }

 private:
  const DisplayModel& model_;
  const std::vector<LayerDiffraction>* diffraction_;  // null: none
  std::optional<JointPass> joint_;                    // the plain or diffracted forward model's pass
  std::optional<ResponsePass> response_;              // or the response's
  const Patterns* t_ = nullptr;                       // last given to Light
  Patterns seen_;                                     // D t
  LightField light_;                                  // L(t) (not with the response: its pass keeps it)
  LightField effective_;                              // L - v (Transposed)
};

}  // namespace layerlab
