// The solvers' vocabulary, apart from their machinery (in the manner of
// ceres/types.h): the options a solve takes, the report it gives, the passes
// and memory a solver declares, and the enums they name. What includes this
// sees the light field and small leaf headers, not the kernels.
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "layerlab/kernels/workspace_pass.h"
#include "layerlab/metrics/retinal_metrics.h"
#include "layerlab/retina/scene_radiance.h"
#include "layerlab/systems/flicker_verdict.h"

namespace layerlab {

// What the display's retinal images are compared with.
enum class RetinalTarget { kLightField, kTraced };

// One pupil position of an eyebox distribution: where the pupil's centre sits
// relative to the scene eye's (its pupil_offset), and its weight.
struct PupilWeight {
  double offset_x_m = 0, offset_y_m = 0;
  double weight = 1;
};

struct RetinalObjectiveOptions {
  std::vector<double> states_diopters;  // D; empty: the eye's accommodation_range in kDefaultStateStep steps
  std::vector<double> weights;          // one per state; empty: every state 1
  double resolution_rad = 0;            // rad per retinal sample; 0: one sample per light-field pixel
  // kLightField: A_a of the target light field. kTraced: RetinaOfScene of `target_radiance`, which whoever
  // holds the target scene sets (Target::Natural, analysis/target_source.h); the objective refuses kTraced without it.
  RetinalTarget target = RetinalTarget::kLightField;
  SceneRadiance target_radiance;
  // Weight each state's residual by the eye's contrast sensitivity (eye/contrast_sensitivity.h):
  // || C (A_a L - r_a) ||^2 with C the gain S(f) at spatial frequency f, the image taken as periodic.
  bool contrast_sensitivity = false;
  // The pupil positions the objective weighs (an eyebox distribution: EyeboxPupils), each seen at every state:
  // f = sum_p w_p sum_a w_a || A_ap (L - l) ||^2, the w_p scaled to sum to 1. Empty: the scene eye's pupil alone.
  std::vector<PupilWeight> pupils;
};
inline constexpr double kDefaultStateStep = 0.2;  // D
inline constexpr double kMaxEyeboxRange = 0.01;   // m: SolverOptions::eyebox_range_m
inline constexpr int kMaxEyeboxPupils = 81;       // pupil positions of an eyebox grid (each its own tables)

// What to do with target values the display cannot reach (above the sum of
// its branch weights in a channel).
enum class TargetRange { kClip, kScale };
std::string ToString(TargetRange r);

// What the solver minimizes: the light-field error (paper Eq. 6), or the
// retinal-space error over the eye's focal stack (solvers/retinal_objective.h;
// quasi-newton and joint minimize it, SolverType::retinal_objective).
enum class ObjectiveKind { kLightField, kRetinal };
std::string ToString(ObjectiveKind k);
// The objective named "lightfield" or "retinal", or nullopt.
std::optional<ObjectiveKind> ObjectiveKindNamed(const std::string& name);

struct SolverOptions {
  // Outer iterations (hybrid: passes over all multiplicative sets). Change it
  // to trade time for error; the trace shows where the error stops improving.
  int iterations = 30;
  // Hybrid: updates of one set before moving on (the paper's 3).
  int sub_iterations = 3;
  // quasi-newton: the first iterations made by the hybrid solver, whose
  // early steps gain more per second; 0 starts with quasi-Newton steps.
  int warm_start_iterations = 0;
  // Wall-clock budget in seconds; 0 means none. Checked between iterations.
  double time_budget = 0;
  // Stop when the objective changes by less than this, relative; 0 runs every iteration.
  double tolerance = 0;
  // For random initial patterns.
  uint64_t seed = 1;
  // Initial transmittance of every pixel, or "random" in [0.25, 0.75] when negative.
  double initial_value = 0.5;
  // A warm start: begin from these patterns (a previous solve's, e.g. for the
  // eye's previous position) instead; they must fit the display's layers.
  const std::vector<struct LayerPattern>* initial_patterns = nullptr;
  // Worker threads; 0 lets the solve choose: every core, but one thread per
  // 16384 rays (this process's share) with the light-field objective, where
  // a smaller share costs more in starting and joining threads than it saves.
  int threads = 0;
  // Multiplicative updates: denominators below this keep the pixel as is,
  // and transmittance never drops below `floor`, so no pixel locks at zero.
  double epsilon = 1e-12;
  double floor = 1e-6;
  TargetRange target_range = TargetRange::kClip;
  ObjectiveKind objective = ObjectiveKind::kLightField;
  RetinalObjectiveOptions retinal;  // the states and their weights, with ObjectiveKind::kRetinal
  // The retinal objective over an eyebox distribution of pupils (retinal.pupils, when that is empty):
  // a square grid within eyebox_range of the eye's pupil in x and y, eyebox_step apart (0: the range, a
  // 3 x 3 grid), weighted uniformly or by a Gaussian of eyebox_sigma (0: uniform). 0 range: the eye's pupil.
  double eyebox_range_m = 0, eyebox_step_m = 0, eyebox_sigma_m = 0;
  // With the light-field objective: also measure the focal-stack PSNR of
  // every trace row, off the clock (the trace's seconds leave it out), so
  // that both objectives' solutions compare at equal solver time.
  bool measure_focal_stack = false;
  // With it or the retinal objective: also these metrics of the focal stack (metrics/retinal_metrics.h; its
  // PSNR is focal_stack_psnr_db already), each the mean over the states of the display's retinal image against
  // the target's, off the clock, at iterations 0, 1, 2, 3, 5, 8, 12, ... (each about kMetricRowGrowth x the
  // last) and the last: each costs a few retinal images' worth of filtering.
  std::vector<const RetinalMetric*> measure_metrics;
  MetricSettings metric_settings;  // how they are measured (foveal weighting, the JND's exponent)
  // Solve through the panels' diffraction (systems/panel_diffraction.h): the
  // forward model reads D t, the patterns as the eye sees them through the
  // panels in front, instead of t. Only where a panel diffracts (fill_factor
  // below 1 in front of another layer of its stack), and only by the solvers
  // whose SolverType::panel_diffraction says so.
  bool panel_diffraction = false;
  // Solve through the panels' liquid-crystal response (systems/lc_response.h):
  // the forward model is the frame's time average of what the panels show
  // as they relax between subframes (solvers/response_pass.h), not the
  // driven patterns. Only where a panel responds in finite time across
  // subframes, and only by the solvers whose SolverType::lc_response says so.
  bool lc_response = false;
  // Called after every iteration with its trace row (progress display); may be empty.
  std::function<void(const struct IterationRecord& row)> progress;
  // Asked after every iteration; true stops the solve with the patterns of
  // that iteration, usable (Ctrl-C: framework/interrupt.h). May be empty.
  std::function<bool()> interrupted;

  // Checkpoints: called after every `checkpoint_every` iterations with what a
  // resumed solve needs (solver_checkpoint.h). Empty or 0: none.
  std::function<void(const struct SolverCheckpoint&)> checkpoint;
  int checkpoint_every = 0;
  // Resuming: continue from a checkpoint of the same solver, display and
  // target; the resumed solve reaches the same patterns as an uninterrupted
  // one (quasi-newton: its curvature pairs are not kept, so it goes on from
  // the checkpoint's patterns with a fresh memory, and a checkpoint written
  // during its warm start resumes with quasi-Newton steps).
  const struct SolverCheckpoint* resume = nullptr;

  // False with "field: value: constraint" in *error when an option is out of range.
  bool IsValid(std::string* error) const;
};

// The grid of pupil positions eyebox_range, _step and _sigma name (row by row from the lowest y, x rising; the
// objective scales the weights to sum to 1); empty when eyebox_range is 0.
std::vector<PupilWeight> EyeboxPupils(const SolverOptions& o);
// The retinal objective's options of a solve: `retinal`, its pupils the eyebox grid's when it names none.
RetinalObjectiveOptions RetinalOptionsOf(const SolverOptions& o);

enum class Termination { kNotRun, kIterationLimit, kTimeBudget, kConverged, kInterrupted, kInvalidOptions, kFailed };
std::string ToString(Termination t);

struct IterationRecord {
  int iteration = 0;     // 0 is the initial guess
  double seconds = 0;    // wall time since the solve started
  double objective = 0;  // sum of squared errors over rays and channels
  double psnr_db = 0;    // peak 1 (display-relative units); +inf for a perfect fit
  // With the retinal objective `objective` is the retinal one, psnr_db stays
  // the light field's, and this is the mean over states of the retinal PSNR;
  // NaN with the light-field objective.
  double focal_stack_psnr_db = std::numeric_limits<double>::quiet_NaN();
  // The focal stack's perceptual metrics (SolverOptions::measure_metrics), each the mean over states; NaN where
  // not measured.
  double focal_stack_ssim = std::numeric_limits<double>::quiet_NaN();
  double focal_stack_ms_ssim = std::numeric_limits<double>::quiet_NaN();
  double focal_stack_jnd = std::numeric_limits<double>::quiet_NaN();
};

struct SolverReport {
  std::string solver;
  std::string objective = "lightfield";  // ToString(SolverOptions::objective): what `trace` and final_objective are
  // The focal stack's target images (RetinalObjectiveOptions::target), when a focal stack was measured.
  std::string retinal_target = "lightfield";
  bool contrast_sensitivity = false;  // the retinal objective's residuals weighted by it
  bool panel_diffraction = false;     // the forward model saw the panels' diffraction
  bool lc_response = false;           // the forward model saw the panels' LC response
  // The light-field PSNR of what the panels show over a frame through their liquid-crystal response
  // (systems/lc_response.h), when it matters (a time-multiplexed display whose panels respond in finite
  // time): the solvers assume instant panels, and psnr_db is that model's. NaN otherwise.
  double shown_psnr_db = std::numeric_limits<double>::quiet_NaN();
  // Whether the solved patterns flicker visibly (analysis/flicker_check.h sets it; a display of one subframe
  // has none).
  std::optional<FlickerVerdict> flicker;
  size_t pupil_positions = 1;  // the focal stack's pupil positions (an eyebox distribution's, or 1)
  Termination termination = Termination::kNotRun;
  std::string message = "not run";
  int iterations = 0;
  double seconds = 0;  // from the initial guess on: `setup_seconds` come before
  // Preparing the target and the solver's work buffers (a fresh light field
  // costs a quarter to half a second of page faults on a virtual machine).
  double setup_seconds = 0;
  double initial_objective = 0, final_objective = 0, final_psnr_db = 0;
  size_t rays = 0;
  int threads = 0;  // worker threads the solve ran on (per process)
  // The fewest an iteration ran on: below `threads` where other processes kept the cores busy (the results are
  // the same bits: framework/fixed_parts.h).
  int threads_min = 0;
  // Target preparation: how many values were beyond the display's range and what was done.
  size_t out_of_range = 0;
  double target_scale = 1;
  std::vector<std::string> warnings;
  std::vector<IterationRecord> trace;

  bool IsSolutionUsable() const;
  std::string BriefReport() const;
  std::string FullReport() const;
};

// What a solve of `time_budget` seconds would have reported, read off a
// longer solve's trace: the trace up to the first iteration at or past the
// budget, where the solve loop checks it (the report unchanged when the solve
// ended sooner; a budget of 0 is none). nullopt when the trace cannot tell: an unusable or
// interrupted solve, or one that stopped on a shorter budget of its own.
std::optional<SolverReport> ReportWithTimeBudget(const SolverReport& report, double time_budget);
// The message of a solve stopped by its time budget after `seconds`.
std::string TimeBudgetMessage(double seconds);

// What a solver holds beyond what every solve holds (solvers/memory_estimate.h
// adds the target, its prepared copy, the patterns and the solve's workspace).
struct SolverMemory {
  int light_fields = 0;  // light-field-sized float buffers of its own (hybrid: the chase)
  // Vectors of one double per layer value of its own, each in huge pages
  // (HugePageAllocator; quasi-newton: work vectors and pairs).
  double layer_doubles = 0;
  // The light fields are freed before the layer vectors are made
  // (quasi-newton: the warm start's chase, then the steps' vectors), so
  // only the larger of the two is held at once.
  bool fields_then_layers = false;
  // The passes it makes (WorkspacePass): what the solve loop sizes its workspace for.
  unsigned passes = kAllPasses;
};

}  // namespace layerlab
