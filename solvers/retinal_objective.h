// The retinal-space (focal-stack) objective: what the eye sees of the
// display, against what it sees of the target, over its accommodation range.
//
//   f(L) = sum_a w_a || A_a (L - l) ||^2
//
// summed over accommodation states a, retinal samples and channels, with
// A_a the retinal operator of state a (retina/retinal_operator.h: natural
// viewing of a light field through the eye's pupil samples, the eye's
// per-channel focus included), L the display's light field, l the target's.
// Its gradient in L is 2 M (L - l) with M = sum_a w_a A_a^T A_a; through the
// display's Jacobian J (kernels/joint_pass.h) the gradient in the patterns
// is 2 J^T M (L - l) (solvers/retinal_pass.h).
//
// The target's retinal images are A_a l by default: natural viewing of the
// very rays the display is asked to reproduce. With a traced target they are
// traced from the target scene itself through the same pupil samples and
// retinal grid (RetinaOfScene), so detail finer than the target's views and
// its true defocus blur enter the objective: f(L) = sum_a w_a || A_a L - r_a ||^2.
//
// With the contrast-sensitivity weighting each residual is filtered by the
// eye's sensitivity S(f) <= 1 first: f = sum_a w_a || C (A_a L - r_a) ||^2,
// gradient 2 sum_a w_a A_a^T C^T C (A_a L - r_a), C^T C the gain S(f)^2.
// The focal-stack PSNR stays the unweighted one.
//
// M is symmetric with non-negative entries, so its largest eigenvalue is at
// most the largest entry of M 1 (Gershgorin); Bound() returns that entry,
// which the solvers divide by so that the light-field objective's step
// sizes stay safe (M / Bound() <= I).
//
// Over an eyebox distribution of pupils (RetinalObjectiveOptions::pupils)
// every state is seen from each pupil position p, with its own operator:
// f = sum_p w_p sum_a w_a || A_ap (L - l) ||^2, sum_p w_p = 1, and M sums
// the pupils' terms likewise.
#pragma once

#include <memory>
#include <vector>

#include "layerlab/framework/lightfield.h"
#include "layerlab/retina/retinal_operator.h"
#include "layerlab/solvers/types.h"
#include "layerlab/systems/display_model.h"

namespace layerlab {

class RetinalObjective {
 public:
  // `target` must outlive this object only during construction (its retinal images are kept).
  RetinalObjective(const DisplayModel& model, const LightField& target, const RetinalObjectiveOptions& options);

  const std::vector<double>& states() const { return states_; }
  const std::vector<double>& weights() const { return weights_; }
  const RetinaGrid& retina() const { return grid_; }
  size_t samples_per_state() const { return pupils_.front().op->retinal_values(); }
  size_t pupil_count() const { return pupils_.size(); }
  double Bound() const { return bound_; }
  // The heap bytes of its operators' tables (RetinalObjectiveBytes counts them before it is made).
  size_t TableBytes() const;

  // f(x); *per_state (if given) gets || A_a (x - l) ||^2 of each state, unweighted by the states' weights (over
  // an eyebox, the pupils' weighted mean sum_p w_p || A_ap (x - l) ||^2).
  double Evaluate(const LightField& x, std::vector<double>* per_state = nullptr) const;
  // f(x), and *m_r = M (x - l) (half the gradient in the light field).
  double EvaluateWithAdjoint(const LightField& x, std::vector<double>* per_state, LightField* m_r) const;

  // The focal-stack PSNR: the mean over states of each state's PSNR (peak 1).
  double FocalStackPsnr(const std::vector<double>& per_state) const;
  // Each metric of the display's retinal images of x against the target's, the mean over states (over an
  // eyebox, the pupils' weighted mean), in the order given; `white_cd_m2` the luminance of display-relative 1;
  // `settings` the user's (foveal weighting, the JND's exponent). Throws layerlab::Error when the grid is
  // smaller than a metric takes.
  std::vector<double> MeanScores(const LightField& x, const std::vector<const RetinalMetric*>& metrics,
                                 double white_cd_m2, const MetricSettings& settings = {}) const;

 private:
  struct Pupil {
    double weight = 1;                              // w_p
    std::unique_ptr<RetinalOperator> op;            // every state's A_ap
    std::vector<std::vector<float>> target_images;  // A_ap l, or r_ap traced
  };
  std::vector<double> states_, weights_;
  std::vector<Pupil> pupils_;
  // The display's retinal images, kept between calls so that each evaluation touches no fresh pages (14 states of
  // 400 x 200 x 3 floats are 13 MB): one evaluation at a time per objective.
  mutable std::vector<std::vector<float>> images_;
  double bound_ = 1;
  RetinaGrid grid_;
  bool contrast_sensitivity_ = false;
  // The weighted errors of images_ (residuals on entry, C^T C residuals on return), per state.
  std::vector<double> WeightResiduals() const;
  // Adds pupil p's w_p-weighted errors to *errors and *f, and its adjoint to *m_r (`first`: written).
  void AddPupil(const Pupil& p, const LightField& x, std::vector<double>* errors, double* f, LightField* m_r,
                bool first) const;
};

// What a RetinalObjective of `options` for `model` allocates, in heap bytes
// (framework/heap_block.h, huge_page_allocator.h), known before it is made:
// for the memory estimate (solvers/memory_estimate.h).
struct RetinalObjectiveMemory {
  size_t pupils = 1;  // pupil positions, an operator each
  size_t tables = 0;  // every pupil's retinal operator's (RetinalOperator::TableBytes)
  size_t images = 0;  // one set of retinal images, every state's: each pupil's target's and the display's are kept
  size_t apply_buffer = 0;  // one operator's Apply buffer, each kept
  // While a traced target is the rays of a light field (LightFieldRays): the
  // workspace its retinal images are made in (RetinaWorkspace::Layout of
  // LightFieldRetinaSizes), freed before Bound() runs.
  size_t retina_workspace = 0;
  // While it is made, on top of what it keeps: the larger of retina_workspace
  // and Bound()'s two light fields and a set of images.
  size_t construction = 0;
  // While it evaluates with the contrast-sensitivity weighting: each thread's filtered field.
  size_t filter = 0;
  size_t kept() const { return tables + (pupils + 1) * images + pupils * apply_buffer; }
};
RetinalObjectiveMemory RetinalObjectiveBytes(const DisplayModel& model, const RetinalObjectiveOptions& options,
                                             int threads);

// The states a RetinalObjectiveOptions names for this eye (its own, or the accommodation range in 0.2 D steps).
std::vector<double> RetinalStates(const EyeModel& eye, const RetinalObjectiveOptions& options);
// The pupil samples of each pupil position the options name (the eye's alone when they name none; those of
// weight 0 left out) and the positions' weights scaled to sum to 1; refuses a negative, non-finite or all-zero
// weight.
std::vector<std::vector<PupilPoint>> RetinalPupils(const EyeModel& eye, const RetinalObjectiveOptions& options,
                                                   std::vector<double>* weights = nullptr);
// The objective's retinal grid over the light field's window as seen from the eyebox center: `resolution_rad`
// per sample, or, at 0, one sample per light-field pixel.
RetinaGrid RetinalObjectiveGrid(const LightFieldGeometry& g, double resolution_rad);

}  // namespace layerlab
