#include "layerlab/solvers/solve_loop.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "layerlab/framework/error.h"
#include "layerlab/framework/fixed_order_sum.h"
#include "layerlab/framework/mpi_ranks.h"
#include "layerlab/framework/params.h"
#include "layerlab/framework/thread_budget.h"
#include "layerlab/kernels/joint_pass.h"
#include "layerlab/kernels/synthesis.h"
#include "layerlab/solvers/response_pass.h"
#include "layerlab/solvers/solver_checkpoint.h"
#include "layerlab/solvers/trace_columns.h"
#include "layerlab/systems/lc_response.h"
#include "layerlab/systems/source_spread.h"

namespace layerlab {

SolveLoop::SolveLoop(std::string solver, const DisplayModel& model, const LightField& target,
                     const SolverOptions& options, Patterns* patterns)
    : model_(model), source_(target), options_(options), patterns_(patterns) {
  report_.solver = std::move(solver);
  report_.objective = ToString(options.objective);
  if (options.retinal.target == RetinalTarget::kTraced) report_.retinal_target = "traced";
  report_.contrast_sensitivity = options.objective == ObjectiveKind::kRetinal && options.retinal.contrast_sensitivity;
  start_ = std::chrono::steady_clock::now();
}

SolveLoop::~SolveLoop() {
  if (saved_threads_) omp_set_num_threads(saved_threads_);
}

double SolveLoop::Seconds() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

int SolveLoop::AutomaticThreads() const {
  const int cores = omp_get_max_threads();
  // The retinal images' work does not scale with the rays.
  if (options_.objective == ObjectiveKind::kRetinal || options_.measure_focal_stack) return cores;
  const size_t rays = model_.geometry().ray_count();
  return static_cast<int>(std::clamp<size_t>((rays + kRaysPerThread - 1) / kRaysPerThread, 1, cores));
}

bool SolveLoop::Start(const std::string& refusal) {
  if (!refusal.empty()) {
    Fail(refusal);
    return false;
  }
  std::string error;
  if (!options_.IsValid(&error)) {
    report_.termination = Termination::kInvalidOptions;
    report_.message = error;
    return false;
  }
  const int threads = options_.threads > 0 ? options_.threads : AutomaticThreads();
  saved_threads_ = omp_get_max_threads();
  omp_set_num_threads(threads);
  parts_.emplace(threads);
  threads_.emplace(threads);
  report_.threads = report_.threads_min = threads;
  try {
    RequireSameRays(model_, source_);
    prepared_ = PrepareTarget(model_, source_, options_.target_range, &report_);
    const SolverType* type = SolverRegistry::Builtins().find(report_.solver);
    if (!KeepsConstrainedLayers(type)) return false;
    if (!SetUpForwardModel(type)) return false;
    unsigned passes = type ? type->memory.passes : unsigned(kAllPasses);
    if (!plain_forward()) passes |= kJointPass | kSynthesisPass;  // the forward model then runs through these
    workspace_ = std::make_unique<SolveWorkspace>(model_, omp_get_max_threads(), passes);
    if (options_.objective == ObjectiveKind::kRetinal || options_.measure_focal_stack)
      retinal_ = std::make_unique<RetinalObjective>(model_, target(), RetinalOptionsOf(options_));
    if (retinal_) report_.pupil_positions = retinal_->pupil_count();
  } catch (const Error& e) {
    Fail(e.what());
    return false;
  }
  report_.rays = static_cast<size_t>(SumAcrossRanks(double(model_.geometry().ray_count())));  // every rank's
  if (const SolverCheckpoint* c = options_.resume) return Resume(*c);
  if (const Patterns* warm = options_.initial_patterns) {
    bool fits = warm->size() == model_.layer_count();
    for (size_t k = 0; fits && k < warm->size(); ++k)
      fits = (*warm)[k].pixel_count() == model_.projection(k).pixel_count() &&
             (*warm)[k].rgb.size() == 3 * (*warm)[k].pixel_count();
    if (!fits) throw Error("warm start: the patterns are not this display's layers");
    *patterns_ = *warm;
    HoldLayerConstraints(model_, patterns_);
  } else {
    *patterns_ = InitialPatterns(model_, options_);
  }
  AdjustThreads(/*after_record=*/false);  // iteration 0 too runs on the threads the load leaves
  const auto now = std::chrono::steady_clock::now();
  report_.setup_seconds = std::chrono::duration<double>(now - start_).count();
  start_ = now;
  bool recorded = false;
  if (retinal()) {
    const RetinalMeasures m = MeasureRetinal();
    report_.initial_objective = m.objective;
    recorded = Record(m.objective, m.light_field_objective, m.focal_stack_psnr_db);
  } else {
    const double objective = PatternsObjective();
    report_.initial_objective = objective;
    recorded = Record(objective, objective,
                      retinal_ ? MeasureRetinal().focal_stack_psnr_db : std::numeric_limits<double>::quiet_NaN());
  }
  if (recorded && MetricRowDue()) MeasureMetrics();
  return recorded && !stopped_;
}

void SolveLoop::MeasureMetrics() {
  const auto begin = std::chrono::steady_clock::now();
  try {
    const LightField light = Light();
    const std::vector<double> scores =
        retinal_->MeanScores(light, options_.measure_metrics, model_.white_luminance(), options_.metric_settings);
    for (size_t k = 0; k < scores.size(); ++k)
      if (options_.measure_metrics[k]->name != "psnr")
        FocalStackColumn(*options_.measure_metrics[k]).set(&report_.trace.back(), scores[k]);
  } catch (const Error& e) {  // the solve stands; the metrics are left unmeasured from here on
    report_.warnings.push_back(std::string("the focal stack's metrics were not measured: ") + e.what());
    options_.measure_metrics.clear();
  }
  metric_row_ = iteration_;
  next_metric_row_ = std::max(iteration_ + 1, static_cast<int>(std::ceil(iteration_ * kMetricRowGrowth)));
  start_ += std::chrono::steady_clock::now() - begin;
}

bool SolveLoop::KeepsConstrainedLayers(const SolverType* type) {
  if (!type || type->fixed_layers) return true;
  for (size_t k = 0; k < model_.layer_count(); ++k) {
    if (!IsConstrainedLayer(model_, k)) continue;
    const PanelSpec& panel = model_.system().layers[k].panel;
    const std::string what = IsFixedLayer(model_, k)
                                 ? " shows a fixed pattern (" + panel.fixed_pattern_file + ")"
                                 : " emits " + panel.emitter->description + ", solved only at its LEDs";
    std::vector<std::string> able;  // the solvers that keep it and suit this display
    const SolverRegistry& registry = SolverRegistry::Builtins();
    for (const std::string& name : registry.names())
      if (registry.get(name).fixed_layers && registry.get(name).Unsuitable(model_.system()).empty())
        able.push_back(name);
    Fail("layer " + model_.system().layers[k].name + what + ", which the " + report_.solver + " solver would change: " +
         (able.empty()
              ? std::string("no solver here keeps ") + (IsFixedLayer(model_, k) ? "a fixed layer" : "an LED layer") +
                    " of a display like this one (the multiplicative solver, which does, solves one stack)"
              : "solve this display with the " + JoinWords(able) + " solver, which keeps it"));
    return false;
  }
  return true;
}

bool SolveLoop::SetUpForwardModel(const SolverType* type) {
  const bool diffracts = options_.panel_diffraction && !PanelDiffraction(model_.system()).empty();
  if (diffracts && !(type && type->panel_diffraction)) {
    Fail("the " + report_.solver + " solver does not model the panels' diffraction (\"panel_diffraction\"); " +
         "joint, multiplicative and quasi-newton do");
    return false;
  }
  response_ = options_.lc_response && ResponseMatters(model_.system());
  if (response_ && !(type && type->lc_response)) {
    Fail("the " + report_.solver + " solver does not model the panels' liquid-crystal response (\"lc_response\"); " +
         "quasi-newton does");
    return false;
  }
  diffraction_ = SeenKernels(model_.system(), diffracts);
  report_.panel_diffraction = diffracts;
  report_.lc_response = response_;
  return true;
}

std::unique_ptr<RayPass> SolveLoop::MakePass() {
  if (response_) return std::make_unique<ResponsePass>(model_, workspace_.get(), diffraction());
  return std::make_unique<JointPass>(model_, workspace_.get(), diffraction());
}

LightField SolveLoop::Light() {
  LightField light(model_.geometry());
  if (response_)
    ShownLightField(model_, ResponseMap(model_.system(), *patterns_), diffraction(), &light, nullptr, workspace_.get());
  else
    Synthesize(model_, Read(), &light, workspace_.get());
  return light;
}

double SolveLoop::PatternsObjective() {
  if (!response_) return Objective(model_, target(), Read(), workspace_.get());
  const LightField light = Light();
  const LightField& l = target();
  return SumAcrossRanks(FixedOrderSquaredDifference(light.rgb.data(), l.rgb.data(), l.rgb.size()));
}

bool SolveLoop::Resume(const SolverCheckpoint& c) {
  if (c.solver != report_.solver) {
    Fail("the checkpoint is of solver \"" + c.solver + "\", not \"" + report_.solver + "\"");
    return false;
  }
  if (c.iteration >= options_.iterations) {
    Fail("the checkpoint is at iteration " + std::to_string(c.iteration) + ", not below the iteration limit " +
         std::to_string(options_.iterations));
    return false;
  }
  report_.setup_seconds = Seconds();
  *patterns_ = c.patterns;
  iteration_ = c.iteration;
  state_ = c.state;
  report_.trace = c.trace;
  report_.initial_objective = c.trace.front().objective;
  report_.final_objective = c.trace.back().objective;
  report_.final_psnr_db = c.trace.back().psnr_db;
  report_.iterations = iteration_;
  start_ = std::chrono::steady_clock::now() -
           std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(c.seconds));
  return true;
}

RetinalMeasures SolveLoop::MeasureRetinal() {
  const auto begin = std::chrono::steady_clock::now();
  const RetinalMeasures m = MeasureRetinalObjective(target(), *retinal_, Light());
  start_ += std::chrono::steady_clock::now() - begin;
  return m;
}

const Patterns& SolveLoop::Read() {
  if (diffraction_.empty()) return *patterns_;
  DiffractPatterns(diffraction_, *patterns_, &seen_);
  return seen_;
}

double SolveLoop::ResumedState(const std::string& key, double fresh) const {
  if (!options_.resume) return fresh;
  auto it = options_.resume->state.find(key);
  return it == options_.resume->state.end() ? fresh : it->second;
}

void SolveLoop::WriteCheckpoint() {
  SolverCheckpoint c{report_.solver, iteration_, Seconds(), *patterns_, state_, report_.trace};
  options_.checkpoint(c);
}

bool SolveLoop::Record(double objective, double light_field_objective, double focal_stack_psnr_db) {
  IterationRecord r{iteration_, Seconds(), objective, PsnrDb(light_field_objective, report_.rays * 3),
                    focal_stack_psnr_db};
  report_.trace.push_back(r);
  report_.iterations = iteration_;
  report_.final_objective = objective;
  report_.final_psnr_db = r.psnr_db;
  if (options_.progress) options_.progress(r);
  if (!std::isfinite(objective)) {
    Fail("the objective became " + std::to_string(objective) + " at iteration " + std::to_string(iteration_));
    return false;
  }
  AdjustThreads(/*after_record=*/true);
  return true;
}

void SolveLoop::AdjustThreads(bool after_record) {
  if (report_.threads <= 1) return;
  // The seconds of the iteration just recorded: from the record before it (iteration 0 is the start's
  // other work, not timed).
  const double now = Seconds(), cpu = ProcessCpuSeconds();
  const bool timed = after_record && iteration_ >= 1 && last_recorded_ >= 0;
  const int threads =
      threads_->Next(timed ? now - last_recorded_ : -1, timed && cpu >= 0 && last_cpu_ >= 0 ? cpu - last_cpu_ : -1);
  if (after_record) last_recorded_ = now, last_cpu_ = cpu;
  if (threads != omp_get_max_threads()) omp_set_num_threads(threads);
  report_.threads_min = std::min(report_.threads_min, threads);
}

bool SolveLoop::EndIteration(std::optional<double> objective) {
  if (stopped_) return false;
  ++iteration_;
  double previous = report_.final_objective;
  double value = 0;
  if (retinal()) {
    const RetinalMeasures m = measured_ ? *measured_ : MeasureRetinal();
    measured_.reset();
    value = m.objective;
    if (!Record(value, m.light_field_objective, m.focal_stack_psnr_db)) return false;
  } else {
    value = objective ? *objective : PatternsObjective();
    const double focal_stack =
        retinal_ ? MeasureRetinal().focal_stack_psnr_db : std::numeric_limits<double>::quiet_NaN();
    if (!Record(value, value, focal_stack)) return false;
  }
  if (options_.tolerance > 0 && std::abs(previous - value) <= options_.tolerance * std::max(previous, 1e-300)) {
    report_.termination = Termination::kConverged;
    report_.message = "relative objective change below " + std::to_string(options_.tolerance);
    stopped_ = true;
  } else if (iteration_ >= options_.iterations) {
    report_.termination = Termination::kIterationLimit;
    report_.message = "";
    stopped_ = true;
  } else if (AnyRank(options_.interrupted && options_.interrupted())) {  // all ranks stop together
    report_.termination = Termination::kInterrupted;
    report_.message = "interrupted after iteration " + std::to_string(iteration_);
    stopped_ = true;
  } else if (AnyRank(options_.time_budget > 0 && Seconds() >= options_.time_budget)) {
    report_.termination = Termination::kTimeBudget;
    report_.message = TimeBudgetMessage(Seconds());
    stopped_ = true;
  }
  if (MetricRowDue() || (stopped_ && !options_.measure_metrics.empty() && retinal_ && metric_row_ != iteration_))
    MeasureMetrics();
  // A stop short of the goal also checkpoints, so that the run can go on.
  const bool short_stop =
      stopped_ && (report_.termination == Termination::kInterrupted || report_.termination == Termination::kTimeBudget);
  if (options_.checkpoint && options_.checkpoint_every > 0 &&
      (iteration_ % options_.checkpoint_every == 0 || short_stop))
    WriteCheckpoint();
  return !stopped_;
}

void SolveLoop::Fail(const std::string& message) {
  report_.termination = Termination::kFailed;
  report_.message = message;
  stopped_ = true;
}

void SolveLoop::Converge(const std::string& message) {
  report_.termination = Termination::kConverged;
  report_.message = message;
  stopped_ = true;
}

SolverReport SolveLoop::Finish() {
  report_.seconds = Seconds();
  // (Solved through the response, the PSNR is already what the panels show.)
  if (!response_ && ResponseMatters(model_.system()) && !report_.trace.empty() &&
      report_.termination != Termination::kFailed) {
    // What the panels show over a frame, measured off the clock.
    const LightField shown = ShownLightField(model_, *patterns_, diffraction());
    const LightField& l = target();
    const double error = FixedOrderSquaredDifference(shown.rgb.data(), l.rgb.data(), shown.rgb.size());
    report_.shown_psnr_db = PsnrDb(SumAcrossRanks(error), report_.rays * 3);  // every rank's rays
  }
  // A solve that ended outside EndIteration (converged): its last row's metrics.
  if (!options_.measure_metrics.empty() && retinal_ && !report_.trace.empty() && metric_row_ != iteration_ &&
      report_.termination != Termination::kFailed)
    MeasureMetrics();
  workspace_.reset();
  if (report_.termination == Termination::kNotRun && !report_.trace.empty()) {
    report_.termination = Termination::kIterationLimit;
    report_.message = "";
  }
  if (report_.IsSolutionUsable())
    if (std::optional<std::string> w = FarBelowWarning(model_, report_)) report_.warnings.push_back(*w);
  return report_;
}

}  // namespace layerlab
