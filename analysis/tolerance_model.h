// The scene as `layerlab tolerance` perturbs it: every tolerance of a
// ToleranceSpec becomes degrees of freedom of named elements, and a draw of
// values for them becomes a perturbed scene document, edited by key and
// compiled by the ordinary reader of each element type.
//
// First every panel placed by "virtual_depth" is placed by its physical
// "distance" from the lens in front of it (the nominal compile's), so that a
// perturbation moves the hardware and not the image. Then, per degree of freedom:
//  - panel_decentre, panel_tilt: each lc_panel's "offset" and "tilt", x and y;
//  - lens_decentre, lens_tilt: each lens of real surfaces ("lens"), x and y
//    (an ideal thin_lens has neither);
//  - gap: the axial place of each panel, one error per panel added to
//    everything behind it in its stack (a stack's spacers add up), and the
//    "gap" of a lens or mirror that gives one; the magnifier's place is the
//    eye's eye_relief, not an assembly gap;
//  - focal_length: a thin_lens's "focal_length" times 1 + e, a lens's radii
//    times 1 + e (its focal length about 1 + e).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "layerlab/analysis/tolerance_spec.h"
#include "layerlab/systems/display_system.h"
#include "layerlab/systems/scene.h"

namespace layerlab {

struct ToleranceDof {
  ToleranceKind kind = ToleranceKind::kGap;
  double limit = 0;     // the tolerance's, SI
  std::string element;  // its name
  size_t index = 0;     // in the document's "elements"
  int axis = 0;         // 0: x, 1: y (decentres and tilts)
  // A panel's gap: the degrees of freedom whose sum moves it (itself and the
  // panels in front of it in its stack), when it is placed by "distance".
  std::vector<size_t> moved_by;
  std::string Name() const;  // "gap front_a", "panel_tilt rear_b x"
};

// One value per degree of freedom, SI.
using ToleranceDraw = std::vector<double>;

class ToleranceModel {
 public:
  // Throws layerlab::Error for a panel it cannot place physically (a
  // "virtual_depth" with no lens or curved mirror in front of it).
  ToleranceModel(const Scene& scene, const DisplaySystem& nominal, const ToleranceSpec& spec);

  const std::vector<ToleranceDof>& dofs() const { return dofs_; }
  // Tolerances given that apply to nothing in this scene, and why.
  const std::vector<std::string>& notes() const { return notes_; }
  const ToleranceSpec& spec() const { return spec_; }

  // Monte Carlo sample `sample` of run `seed`: each value DrawTruncatedNormal
  // of its limit, from a generator seeded by (seed, sample) alone.
  ToleranceDraw Draw(uint64_t seed, uint64_t sample) const;
  // Every degree of freedom of `kind` at sign x its limit, the others at 0.
  ToleranceDraw AtLimit(ToleranceKind kind, double sign) const;
  ToleranceDraw Zero() const { return ToleranceDraw(dofs_.size(), 0.0); }

  // The scene document with `draw` applied (the physical placements of the nominal one at a zero draw).
  nlohmann::json Perturbed(const ToleranceDraw& draw) const;
  // The perturbed document compiled; errors name the draw's file as "<scene> (perturbed)".
  DisplaySystem Compile(const ToleranceDraw& draw) const;

 private:
  void AddPanelDofs(const DisplaySystem& nominal);
  void AddOpticDofs(const Scene& scene);

  ToleranceSpec spec_;
  std::string file_;
  nlohmann::json physical_;
  std::vector<ToleranceDof> dofs_;
  std::vector<std::string> notes_;
};

}  // namespace layerlab
