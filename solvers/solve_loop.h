// The bookkeeping every iterative solver shares: validate options, prepare
// the target and the initial patterns, then record error against wall time
// after each iteration and decide when to stop.
#pragma once

#include <chrono>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include "layerlab/framework/fixed_parts.h"
#include "layerlab/framework/thread_budget.h"
#include "layerlab/kernels/ray_pass.h"
#include "layerlab/solvers/objective.h"
#include "layerlab/solvers/retinal_pass.h"
#include "layerlab/solvers/solver.h"
#include "layerlab/systems/panel_diffraction.h"

namespace layerlab {

class SolveLoop {
 public:
  SolveLoop(std::string solver, const DisplayModel& model, const LightField& target, const SolverOptions& options,
            Patterns* patterns);
  ~SolveLoop();

  // False (and the report says why) when the solve cannot start. The clock
  // of the trace starts here; the time since construction (preparing the
  // target, and whatever the solver allocated before calling this) is the
  // report's setup_seconds. A non-empty `refusal` (why the display does not
  // suit the solver, SolverType::unsuitable in the solver's words) fails first.
  bool Start(const std::string& refusal = "");
  const LightField& target() const { return prepared_ ? *prepared_ : source_; }
  // The working memory of the solve's passes, made in Start for the model,
  // the solver's passes (SolverMemory::passes) and the thread count, and
  // released in Finish.
  SolveWorkspace& workspace() { return *workspace_; }
  int iteration() const { return iteration_; }  // iterations completed
  double Seconds() const;

  // Runs `work` off the trace's clock, its time counted in setup_seconds:
  // set-up a solver can only do after it has started (memory an earlier
  // phase of the solve frees first, so that the two are not held at once).
  template <class Work>
  void SetUpMidway(Work work) {
    const auto begin = std::chrono::steady_clock::now();
    work();
    const auto spent = std::chrono::steady_clock::now() - begin;
    start_ += spent;
    report_.setup_seconds += std::chrono::duration<double>(spent).count();
  }

  // Records the objective after an iteration; false when it is time to stop.
  // `objective` may be passed when the solver computed it anyway. With the
  // retinal objective the trace row is the retinal measures: those passed
  // to SetMeasures for this iterate, or measured here.
  bool EndIteration(std::optional<double> objective = std::nullopt);
  // With the retinal objective (options.objective): the objective of the
  // prepared target, made in Start(); nullptr otherwise.
  const RetinalObjective* retinal() const {
    return options_.objective == ObjectiveKind::kRetinal ? retinal_.get() : nullptr;
  }
  void SetMeasures(const RetinalMeasures& m) { measured_ = m; }
  // With options.panel_diffraction and panels that diffract: the forward
  // model's D (systems/panel_diffraction.h), which the solver hands to its
  // passes; nullptr otherwise. The loop's own objectives read D t then.
  const std::vector<LayerDiffraction>* diffraction() const { return diffraction_.empty() ? nullptr : &diffraction_; }
  // With options.lc_response and panels that respond in finite time: the forward model is the frame's time
  // average through the response (solvers/response_pass.h).
  bool response() const { return response_; }
  // Whether the forward model is the plain one, l~(t) (no diffraction, no response).
  bool plain_forward() const { return diffraction_.empty() && !response_; }
  // The pass over the rays of the forward model the options ask for (JointPass, or ResponsePass), in this
  // solve's workspace.
  std::unique_ptr<RayPass> MakePass();
  // Stops with a failure (for example a non-finite objective).
  void Fail(const std::string& message);
  // Stops because no further step can lower the objective.
  void Converge(const std::string& message);

  // Resuming: the state the checkpoint carried (empty for a fresh solve).
  bool resumed() const { return options_.resume != nullptr; }
  double ResumedState(const std::string& key, double fresh) const;
  // What this solver carries between iterations, for checkpoints: set it
  // before EndIteration.
  void SetState(const std::string& key, double value) { state_[key] = value; }
  SolverReport Finish();

 private:
  // Below this many rays per thread (this process's share), an iteration's
  // parallel regions cost more in starting and joining threads than they
  // save (quasi-newton breaks even near 20000 rays on 2 cores), and on a
  // loaded machine each join can wait a whole scheduler time slice.
  static constexpr size_t kRaysPerThread = 16384;
  // The thread count of options.threads = 0.
  int AutomaticThreads() const;
  bool Record(double objective, double light_field_objective, double focal_stack_psnr_db);
  // The threads of the next iteration: at most report_.threads, fewer while other processes keep the cores
  // busy (framework/thread_budget.h).
  void AdjustThreads(bool after_record);
  // The focal stack's metrics (options.measure_metrics) of the patterns now, into the last trace row, off the
  // clock; at the rows kMetricRowGrowth spaces and at the last.
  void MeasureMetrics();
  bool MetricRowDue() const { return !options_.measure_metrics.empty() && retinal_ && iteration_ >= next_metric_row_; }
  // Start's end for a resumed solve: the checkpoint's patterns, trace and state; false (failed) when it is not
  // this solver's or is at the iteration limit already.
  bool Resume(const struct SolverCheckpoint& c);
  // The panels' diffraction and response the options ask for; false (failed) when the solver cannot model them.
  // False (failed) when the display has a fixed or LED layer (IsConstrainedLayer) that the solver would change.
  bool KeepsConstrainedLayers(const SolverType* type);
  bool SetUpForwardModel(const SolverType* type);
  // Measured here, off the clock (the solver did not spend it).
  RetinalMeasures MeasureRetinal();
  // The patterns the forward model reads: D t with diffraction, else t itself (without the response).
  const Patterns& Read();
  // The display's light field as the forward model sees it.
  LightField Light();
  double PatternsObjective();
  void WriteCheckpoint();

  const DisplayModel& model_;
  const LightField& source_;
  SolverOptions options_;
  Patterns* patterns_;
  std::optional<LightField> prepared_;  // the target clipped or scaled, if it had to be
  std::unique_ptr<SolveWorkspace> workspace_;
  SolverReport report_;
  std::chrono::steady_clock::time_point start_;
  int iteration_ = 0;
  int saved_threads_ = 0;
  // The solve's sums cut into report_.threads parts (framework/fixed_parts.h), so that an iteration may run on
  // fewer threads where other processes keep the cores busy (AdjustThreads) with the same bits.
  std::optional<ScopedParts> parts_;
  std::optional<IterationThreads> threads_;
  double last_recorded_ = -1, last_cpu_ = -1;  // Seconds() and ProcessCpuSeconds() at the last Record
  bool stopped_ = false;
  std::map<std::string, double> state_;
  std::unique_ptr<RetinalObjective> retinal_;
  std::optional<RetinalMeasures> measured_;
  std::vector<LayerDiffraction> diffraction_;
  bool response_ = false;
  Patterns seen_;            // D t
  int next_metric_row_ = 0;  // the next iteration whose row measures options.measure_metrics
  int metric_row_ = -1;      // the last row that did
};

// The rows that measure the focal stack's metrics: 0, 1, 2, 3, 5, 8, 12, ..., each about this times the last.
inline constexpr double kMetricRowGrowth = 1.5;

}  // namespace layerlab
