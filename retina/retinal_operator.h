// The retinal image of a light field as a linear operator: for one
// accommodation state a, R_a = A_a L, where (A_a L)(i, j) is the mean over
// pupil points u of L read along the ray from u through the in-focus point of
// retinal sample (i, j) (retina/lightfield_radiance.h: the four views around
// u blended bilinearly, each view read at the ray's crossing of the origin
// plane by the layers' sampling rule, 0 outside the window). A_a is what
// RetinaOfLightField computes; this class also applies its transpose
// A_a^T, which scatters a retinal image back onto the light field's rays with
// the same weights, so that solvers can take gradients of retinal-space
// objectives (solvers/retinal_objective.h).
//
// Matrix-free, per pupil point: the views it blends depend on the pupil
// point alone, so they are blended into one image once for every state;
// each state then gathers that image by its per-column and per-row tables
// (the separable structure RetinaOfLightField uses; a per-channel focus,
// chromatic aberration, keeps one table per distinct focus). The transpose
// scatters every state's rows into one image per pupil point, each
// light-field row by one thread, and adds it to the views it blends.
#pragma once

#include <algorithm>
#include <array>
#include <vector>

#include "layerlab/framework/lightfield.h"
#include "layerlab/retina/retina.h"
#include "layerlab/systems/layer_sampler.h"

namespace layerlab {

class RetinalOperator {
 public:
  // One A_a per state; states[a] is state a's focus per channel (ChannelAccommodation).
  RetinalOperator(const LightFieldGeometry& g, Sampling pixels, const RetinaGrid& retina,
                  const std::vector<PupilPoint>& pupil, const std::vector<std::array<double, 3>>& states);
  // One state.
  RetinalOperator(const LightFieldGeometry& g, Sampling pixels, const RetinaGrid& retina,
                  const std::vector<PupilPoint>& pupil, const std::array<double, 3>& accommodation)
      : RetinalOperator(g, pixels, retina, pupil, std::vector<std::array<double, 3>>{accommodation}) {}

  const RetinaGrid& retina() const { return retina_; }
  const LightFieldGeometry& geometry() const { return geometry_; }
  size_t state_count() const { return state_count_; }
  size_t retinal_values() const { return size_t(retina_.cols) * retina_.rows * 3; }

  // Apply keeps its work buffer (kPupilGroup views' pixels) between calls, so
  // that repeated calls touch no fresh pages: one call at a time per operator.
  // (*out)[a] = A_a x: [row][col][channel] of the retinal grid, written whole
  // (its images' memory reused when they have the size already).
  void Apply(const LightField& x, std::vector<std::vector<float>>* out) const;
  // out = sum_a A_a^T y[a] (y as Apply writes it), or out += it with `accumulate`; `out` has x's geometry.
  void ApplyTranspose(const std::vector<std::vector<float>>& y, LightField* out, bool accumulate = false) const;
  // One state's.
  void Apply(const LightField& x, std::vector<float>* out) const;
  void ApplyTranspose(const std::vector<float>& y, LightField* out, bool accumulate = false) const;

  // The heap bytes of the tables an operator of these arguments holds (each block as glibc's malloc lays it
  // out), counted by making its tables one at a time: what the memory estimate counts before the operator exists.
  static size_t TableBytes(const LightFieldGeometry& g, Sampling pixels, const RetinaGrid& retina,
                           const std::vector<PupilPoint>& pupil, const std::vector<std::array<double, 3>>& states);
  // The same of this operator's tables (not its Apply buffer).
  size_t TableBytes() const;
  // The floats Apply keeps between calls: a group of pupil points' blends, a view each.
  size_t ApplyBufferValues() const { return ApplyBufferValues(geometry_, views_.size()); }
  static size_t ApplyBufferValues(const LightFieldGeometry& g, size_t pupil_points) {
    return std::min(kPupilGroup, pupil_points) * g.pixels_per_view() * 3;
  }

 private:
  struct Column {
    int32_t ray, c0, c1;  // retinal column, light-field columns
    float w0, w1;
  };
  // Nearest sampling: `length` retinal columns from `ray` on read the light-field columns from `c` on, one each.
  struct Run {
    int32_t ray, c, length;
  };
  struct Row {
    int32_t k0 = -1, k1 = -1;  // light-field rows; k0 = -1: outside the window
    float w0 = 0, w1 = 0;
  };
  struct Source {
    int32_t ray_row;
    float weight;
  };
  // What the rays of one pupil point read at one focus.
  struct FocusTable {
    std::vector<Column> columns;               // the retinal columns whose rays cross the window
    std::vector<Run> runs;                     // with nearest sampling: `columns` as runs of consecutive columns
    std::vector<Row> rows;                     // per retinal row
    std::vector<std::vector<Source>> sources;  // per light-field row, the retinal rows reading it
  };
  // A state's channels of one focus.
  struct Entry {
    size_t state;
    int channels[3], channel_count = 0;
    std::vector<FocusTable> tables;  // per pupil point
  };
  struct PupilViews {
    size_t view[4];
    float weight[4];  // 1 / pupil count folded in
    int count = 0;
  };
  struct Tangents {
    std::vector<double> x, y;  // tan of each retinal column's and row's angle
  };
  static Tangents TangentsOf(const RetinaGrid& retina);
  // visit(state, focus, channels, channel_count) for each distinct focus of each state: one Entry each.
  template <class Visit>
  static void ForEachFocus(const std::vector<std::array<double, 3>>& states, Visit visit);
  static FocusTable MakeTable(const LightFieldGeometry& g, bool nearest, const RetinaGrid& retina,
                              const Tangents& tangents, const PupilPoint& u, double focus);
  static size_t HeapBytes(const FocusTable& t);

  std::vector<Entry> entries_;
  std::vector<PupilViews> views_;  // per pupil point: the views it blends, the same at every focus
  size_t state_count_ = 0;
  bool nearest_ = true;
  static constexpr size_t kPupilGroup = 8;  // pupil points whose blends Apply keeps at once (a view's pixels each)
  mutable std::vector<float> work_;         // Apply's blends of a group of pupil points
  LightFieldGeometry geometry_;
  RetinaGrid retina_;
};

// The accommodation states of a focal stack: from `from` to `to` diopters in
// steps of `step` (the last at most `to` plus a rounding allowance).
std::vector<double> AccommodationStates(double from, double to, double step);

}  // namespace layerlab
