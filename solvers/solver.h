// Solvers factorize a target light field into layer patterns for a display:
//   argmin_t || l - sum_b w_b prod_{k in b} P_k t_k ||^2,  0 <= t <= 1   (paper Eq. 6)
// Options in, a report out (in the manner of ceres::Solver): a plain options
// struct with IsValid(), and a report that starts as "not run", holds the
// termination reason, a trace row per iteration (error against wall time),
// BriefReport(), FullReport() and IsSolutionUsable(). Solve() does not throw
// for bad options or a failed run: the report says what happened.
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "framework/lightfield.h"
#include "solvers/retinal_objective.h"
#include "systems/display_model.h"
#include "systems/solve_workspace.h"

namespace layerlab {

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
  // With the light-field objective: also measure the focal-stack PSNR of
  // every trace row, off the clock (the trace's seconds leave it out), so
  // that both objectives' solutions compare at equal solver time.
  bool measure_focal_stack = false;
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
};

struct SolverReport {
  std::string solver;
  std::string objective = "lightfield";  // ToString(SolverOptions::objective): what `trace` and final_objective are
  // The focal stack's target images (RetinalObjectiveOptions::target), when a focal stack was measured.
  std::string retinal_target = "lightfield";
  bool contrast_sensitivity = false;  // the retinal objective's residuals weighted by it
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

class Solver {
 public:
  virtual ~Solver() = default;
  // `patterns` holds one pattern per layer; it is initialised by the solver.
  virtual SolverReport Solve(const DisplayModel& model, const LightField& target, const SolverOptions& options,
                             Patterns* patterns) const = 0;
};

// A "solve" key of a scene file that sets a SolverOptions field
// (solvers/solve_config.cpp reads them all).
struct SolverOptionKey {
  std::string key;      // the JSON key, also the field's name
  std::string meaning;  // one line, for listings
};
// The keys every solver reads (the solve loop's: iterations, time_budget, ...).
const std::vector<SolverOptionKey>& CommonSolverOptionKeys();
// sub_iterations: the hybrid's, read also by quasi-newton's warm start.
SolverOptionKey SubIterationsKey();

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

// Everything the rest of the program knows about a solver: adding one is its
// file and a line in builtin_solvers.def (or SolverRegistry::add at run time).
struct SolverType {
  SolverType() = default;
  SolverType(std::string name_, std::string summary_, std::function<std::unique_ptr<Solver>()> make_,
             SolverOptions defaults_ = {})
      : name(std::move(name_)), summary(std::move(summary_)), make(std::move(make_)), defaults(std::move(defaults_)) {}

  std::string name;
  std::string summary;
  std::function<std::unique_ptr<Solver>()> make;
  SolverOptions defaults;  // what this solver runs with unless told otherwise
  // Why it cannot factorize `system`, worded to follow the solver's name
  // ("needs a display of one branch; ..."), or "" when it can. Empty: every display.
  std::function<std::string(const DisplaySystem&)> unsuitable;
  // Among the solvers that suit a display, the one of highest rank is its
  // default (the most specific fit); 0: never chosen by default.
  int default_rank = 0;
  SolverMemory memory;
  // It minimizes the retinal objective when SolverOptions::objective asks (else only the light-field one).
  bool retinal_objective = false;
  // The keys it reads beyond CommonSolverOptionKeys().
  std::vector<SolverOptionKey> options;

  std::string Unsuitable(const DisplaySystem& system) const { return unsuitable ? unsuitable(system) : ""; }
  bool Reads(const std::string& key) const;  // a common key or one of `options`
};

class SolverRegistry {
 public:
  void add(SolverType type);  // fails if the name is taken
  const SolverType* find(const std::string& name) const;
  std::vector<std::string> names() const;
  // Throws layerlab::Error listing the known names for an unknown one.
  const SolverType& get(const std::string& name) const;
  std::unique_ptr<Solver> create(const std::string& name) const { return get(name).make(); }
  // The suitable solver of highest default_rank; throws layerlab::Error when none suits.
  std::string DefaultFor(const DisplaySystem& system) const;

  static const SolverRegistry& Builtins();
  static SolverRegistry WithBuiltins();  // a copy to add to

 private:
  std::map<std::string, SolverType> types_;
};

// Why the named solver cannot factorize `system`, or "" when it can; throws
// layerlab::Error for an unknown name.
std::string UnsuitableSolver(const std::string& solver, const DisplaySystem& system,
                             const SolverRegistry& registry = SolverRegistry::Builtins());

}  // namespace layerlab
