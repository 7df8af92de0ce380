// A compiled display bound to the rays of a light field: one projection per
// layer and per-channel branch weights, so that the synthesized light field
//   l~ = sum_b w_b * prod_{k in b} P_k t_k        (paper Eq. 3-5)
// covers additive (one layer per branch), multiplicative (one branch) and
// hybrid displays with any number of branches and layers.
//
// Units: light-field values are display-relative, as in the paper's Eq. 6
// (where every branch adds with weight 1). A value of 1 is the luminance of
// the brightest branch at full white in its brightest channel
// (white_luminance(), cd/m^2); w_b[c] is branch b's full white in channel c
// relative to it. A half-mirror hybrid thus has w = 1 for both branches and
// can show up to 2; a PBS/HWP hybrid has per-channel weights a little below 1.
// A time-multiplexed display's branches are each one subframe's: white is a
// branch at full white in every subframe, so each weighs 1/K.
#pragma once

#include <array>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "layerlab/framework/lightfield.h"
#include "layerlab/systems/display_system.h"
#include "layerlab/systems/mapped_pairs.h"
#include "layerlab/systems/projection.h"

namespace layerlab {

// A layer's transmittance pattern in [0, 1], [row][col][rgb], in the panel's
// own pixel order (flips already applied by the projection).
struct LayerPattern {
  int cols = 0, rows = 0;
  std::vector<float> rgb;

  LayerPattern() = default;
  LayerPattern(int c, int r, float value) : cols(c), rows(r), rgb(static_cast<size_t>(c) * r * 3, value) {}
  size_t pixel_count() const { return static_cast<size_t>(cols) * rows; }
};
using Patterns = std::vector<LayerPattern>;

class DisplayModel {
 public:
  DisplayModel(const DisplaySystem& system, const LightFieldGeometry& lf, Sampling sampling = Sampling::kNearest);

  const DisplaySystem& system() const { return system_; }
  const LightFieldGeometry& geometry() const { return lf_; }
  Sampling sampling() const { return sampling_; }
  size_t layer_count() const { return projections_.size(); }
  const LayerProjection& projection(size_t k) const { return projections_[k]; }
  size_t branch_count() const { return system_.branches.size(); }
  const std::vector<int>& branch_layers(size_t b) const { return system_.branches[b].layers; }
  const std::array<float, 3>& weight(size_t b) const { return weights_[b]; }
  double white_luminance() const { return white_luminance_; }

  Patterns UniformPatterns(float value) const;

  // Behind real lenses: branch b's rays binned by pixel pair (mapped_pairs.h),
  // made on the first call and kept (so a solve's memory estimate, which asks
  // first, reads them as resident); nullptr where the branch does not suit
  // or binning would not pay. Safe to call from several threads.
  const MappedPairs* pair_list(size_t b) const;

  // The light of branch b alone for one view, w_b prod_k P_k t_k, through
  // the projections (kernels/view_synthesizer.h's Synthesize takes the fast path where it can).
  // `scratch`: a view of samples for layers of several taps per ray (LayerProjection::GatherMultiply).
  void SynthesizeBranchView(size_t b, size_t view, const Patterns& t, float* out,
                            std::vector<float>* scratch = nullptr) const;

 private:
  DisplaySystem system_;
  LightFieldGeometry lf_;
  Sampling sampling_;
  std::vector<LayerProjection> projections_;
  std::vector<std::array<float, 3>> weights_;
  double white_luminance_ = 0;
  struct PairLists {
    std::vector<std::once_flag> made;
    std::vector<std::unique_ptr<const MappedPairs>> lists;
  };
  std::shared_ptr<PairLists> pair_lists_;  // shared by copies, whose projections are the same
};

// The geometry the display itself suggests: its field of view (the farthest
// layer's frustum) cut at the origin plane `origin_diopters` (default: the
// middle of the layers' dioptric range), the farthest layer's pixel count,
// and the eye's views and eyebox.
LightFieldGeometry DisplayLightFieldGeometry(const DisplaySystem& system, double origin_diopters = -1);

// A target light field whose views, eyebox, pixels per view or field (within
// 1 %) differ from DisplayLightFieldGeometry's: one warning naming each
// difference, the display's value beside the target's, since the layers are
// then sampled at the target's rays (none when they agree).
std::vector<std::string> TargetGeometryWarnings(const DisplaySystem& system, const LightFieldGeometry& target);

}  // namespace layerlab
