// The retinal image of a light field as a linear operator: for one
// accommodation state a, R_a = A_a L, where (A_a L)(i, j) is the mean over
// pupil points u of L read along the ray from u through the in-focus point of
// retinal sample (i, j) (systems/lightfield_radiance.h: the four views around
// u blended bilinearly, each view read at the ray's crossing of the origin
// plane by the layers' sampling rule, 0 outside the window). A_a is what
// RetinaOfLightField computes; this class also applies its transpose
// A_a^T, which scatters a retinal image back onto the light field's rays with
// the same weights, so that solvers can take gradients of retinal-space
// objectives (solvers/retinal_objective.h).
//
// Matrix-free: per pupil point the views it blends, per retinal column the
// light-field columns it reads and per retinal row the rows, the separable
// structure that RetinaOfLightField uses; a per-channel focus (chromatic
// aberration) keeps one such table per distinct focus.
#pragma once

#include <array>
#include <vector>

#include "framework/lightfield.h"
#include "systems/layer_sampler.h"
#include "systems/retina.h"

namespace layerlab {

class RetinalOperator {
 public:
  RetinalOperator(const LightFieldGeometry& g, Sampling pixels, const RetinaGrid& retina,
                  const std::vector<PupilPoint>& pupil, const std::array<double, 3>& accommodation);

  const RetinaGrid& retina() const { return retina_; }
  const LightFieldGeometry& geometry() const { return geometry_; }
  size_t retinal_values() const { return size_t(retina_.cols) * retina_.rows * 3; }

  // out = A x: [row][col][channel] of the retinal grid, written whole.
  void Apply(const LightField& x, std::vector<float>* out) const;
  // out = A^T y (y as Apply writes it), or out += A^T y with `accumulate`; `out` has x's geometry.
  void ApplyTranspose(const std::vector<float>& y, LightField* out, bool accumulate = false) const;

 private:
  struct Column {
    int32_t ray, c0, c1;  // retinal column, light-field columns
    float w0, w1;
  };
  struct Row {
    int32_t k0 = -1, k1 = -1;  // light-field rows; k0 = -1: outside the window
    float w0 = 0, w1 = 0;
  };
  struct PupilTable {
    size_t view[4];
    float view_weight[4];  // 1 / pupil count folded in
    int views = 0;
    std::vector<Column> columns;  // the retinal columns whose rays cross the window
    std::vector<Row> rows;        // per retinal row
  };
  // [focus][pupil point]; channel c reads focus_of_[c].
  std::vector<std::vector<PupilTable>> tables_;
  std::array<int, 3> focus_of_{0, 0, 0};
  // Per light-field view, the (focus, pupil point, slot) that read it: the transpose writes one view per thread.
  struct Reader {
    int focus, point, slot;
  };
  std::vector<std::vector<Reader>> readers_;
  LightFieldGeometry geometry_;
  RetinaGrid retina_;
};

// The accommodation states of a focal stack: from `from` to `to` diopters in
// steps of `step` (the last at most `to` plus a rounding allowance).
std::vector<double> AccommodationStates(double from, double to, double step);

}  // namespace layerlab
