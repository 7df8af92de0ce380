#include "layerlab/solvers/solver_option_table.h"

namespace layerlab {
namespace {

using Kind = SolverOptionKind;

OptionRange Closed(double min, double max) { return {min, max, false, false}; }

std::vector<SolverOptionEntry> MakeTable() {
  std::vector<SolverOptionEntry> t;
  SolverOptionEntry e;
  auto add = [&] {
    t.push_back(e);
    e = SolverOptionEntry{};
  };
  // The solve's setting, not a SolverOptions field.
  e.key = "solver", e.kind = Kind::kConfig, e.type = "solver name", e.default_text = "the display's default";
  e.meaning = "multiplicative for one branch, additive-trust-region for one layer per branch, else hybrid";
  e.cli_flag = "--solver", e.cli_help = "Solver", e.python = "solver";
  add();
  e.key = "target", e.kind = Kind::kConfig, e.type = "path", e.default_text = "none";
  e.meaning = "a light-field folder (lightfield/1); not with target_scene";
  e.cli_flag = "--target";
  add();
  e.key = "target_scene", e.kind = Kind::kConfig, e.type = "path", e.default_text = "none";
  e.meaning = "a target scene (layerlab-target/1) rendered with Embree";
  e.cli_flag = "--target-scene";
  add();

  e.key = "iterations", e.kind = Kind::kInteger, e.type = "integer", e.has_range = true;
  e.range = Closed(1, 1000000), e.default_text = "the solver's", e.meaning = "outer iterations";
  e.cli_flag = "--iterations", e.cli_help = "Outer iterations", e.python = "iterations";
  e.integer = &SolverOptions::iterations;
  add();
  e.key = "sub_iterations", e.kind = Kind::kInteger, e.type = "integer", e.has_range = true;
  e.range = Closed(1, 1000), e.default_text = "the solver's";
  e.meaning = "hybrid and quasi-newton: updates of one multiplicative set before the next";
  e.cli_flag = "--sub-iterations", e.cli_help = "Updates per set and outer iteration (hybrid)";
  e.python = "sub_iterations", e.integer = &SolverOptions::sub_iterations;
  add();
  e.key = "warm_start_iterations", e.kind = Kind::kInteger, e.type = "integer", e.has_range = true;
  e.range = Closed(0, 1000000), e.default_text = "the solver's";
  e.meaning = "quasi-newton: hybrid iterations before the quasi-Newton steps";
  e.cli_flag = "--warm-start-iterations";
  e.cli_help = "Iterations made by the hybrid solver before quasi-Newton steps (quasi-newton)";
  e.python = "warm_start_iterations", e.integer = &SolverOptions::warm_start_iterations;
  add();
  e.key = "time_budget", e.kind = Kind::kReal, e.type = "time", e.dimension = Dimension::kTime, e.has_range = true;
  e.range = Closed(0, 1e7), e.constraint_note = " s (0 = none)", e.default_text = "0 s (none)";
  e.meaning = "wall-clock budget";
  e.cli_flag = "--time-budget", e.cli_help = "Stop after this long: seconds, or with units (\"5 s\", \"2 min\")";
  e.python = "time_budget", e.real = &SolverOptions::time_budget;
  add();
  e.key = "tolerance", e.kind = Kind::kReal, e.type = "fraction", e.has_range = true;
  e.range = {0, 1, false, true}, e.default_text = "0 (never)";
  e.meaning = "stop when the objective changes by less than this, relative";
  e.cli_flag = "--tolerance", e.cli_help = "Stop when the objective changes by less than this, relative";
  e.python = "tolerance", e.real = &SolverOptions::tolerance;
  add();
  e.key = "initial_value", e.kind = Kind::kReal, e.type = "fraction", e.has_range = true;
  e.range = Closed(-1, 1), e.constraint_note = ", at least floor unless negative (random)";
  e.default_text = "the solver's", e.meaning = "initial transmittance; negative: random in [0.25, 0.75]";
  e.cli_flag = "--initial-value", e.cli_help = "Initial transmittance (negative: random)";
  e.python = "initial_value", e.real = &SolverOptions::initial_value;
  add();
  e.key = "seed", e.kind = Kind::kSeed, e.type = "integer", e.default_text = "1";
  e.meaning = "for random initial patterns", e.python = "seed", e.seed = &SolverOptions::seed;
  add();
  e.key = "threads", e.kind = Kind::kInteger, e.type = "integer", e.has_range = true;
  e.range = Closed(0, 1024), e.constraint_note = " (0 = all cores)";
  e.default_text = "0 (every core; one per 16384 rays with the light-field objective)";
  e.meaning =
      "worker threads: the most the solve runs on; an iteration runs on fewer while other processes keep the cores "
      "busy, with the same results (report.json `threads`, and `threads_min`: the fewest an iteration ran on)";
  e.cli_flag = "--threads", e.cli_help = "Worker threads (0: all cores)";
  e.python = "threads", e.integer = &SolverOptions::threads;
  add();
  e.key = "sampling", e.kind = Kind::kConfig, e.type = "nearest, bilinear", e.default_text = "nearest";
  e.meaning = "how the light field samples the layers", e.choices = {"nearest", "bilinear"};
  e.cli_flag = "--sampling", e.cli_help = "Layer sampling: nearest or bilinear", e.python = "sampling";
  add();
  e.key = "target_range", e.kind = Kind::kChoice, e.type = "clip, scale", e.default_text = "clip";
  e.meaning = "target values beyond what the display shows: clipped, or the target scaled";
  e.cli_flag = "--target-range", e.cli_help = "Target values beyond the display: clip or scale";
  e.python = "target_range", e.choices = {"clip", "scale"};
  e.get = [](const SolverOptions& o) { return int(o.target_range); };
  e.set = [](SolverOptions& o, int i) { o.target_range = TargetRange(i); };
  add();
  e.key = "objective", e.kind = Kind::kChoice, e.type = "lightfield, retinal", e.default_text = "lightfield";
  e.meaning =
      "what is minimized: the light-field error, or the retinal error over the eye's accommodation_range in 0.2 D "
      "steps (quasi-newton, joint; docs/retinal-objective.md)";
  e.cli_flag = "--objective";
  e.cli_help = "What is minimized: lightfield, or retinal (the focal stack; quasi-newton, joint)";
  e.choices = {"lightfield", "retinal"};
  e.get = [](const SolverOptions& o) { return int(o.objective); };
  e.set = [](SolverOptions& o, int i) { o.objective = ObjectiveKind(i); };
  add();
  e.key = "contrast_sensitivity", e.kind = Kind::kBoolean, e.type = "boolean", e.default_text = "false";
  e.meaning =
      "the retinal objective's residuals weighted by the eye's contrast sensitivity (Mannos and Sakrison 1974, 1 up "
      "to its 7.9 cpd peak)";
  e.cli_flag = "--contrast-sensitivity";
  e.cli_help = "Weight the retinal objective's residuals by the eye's contrast sensitivity (docs/retinal-objective.md)";
  e.get = [](const SolverOptions& o) { return int(o.retinal.contrast_sensitivity); };
  e.set = [](SolverOptions& o, int i) { o.retinal.contrast_sensitivity = i != 0; };
  add();
  e.key = "retinal_target", e.kind = Kind::kChoice, e.type = "lightfield, traced", e.default_text = "lightfield";
  e.meaning =
      "the retinal objective's target images (and the focal-stack PSNR's): natural viewing of the target light "
      "field, or traced from target_scene ray by ray (needs a target scene; seconds per state)";
  e.cli_flag = "--retinal-target";
  e.cli_help =
      "The retinal objective's target images: lightfield (natural viewing of the target light field) or traced "
      "(from --target-scene, ray by ray)";
  e.choices = {"lightfield", "traced"};
  e.get = [](const SolverOptions& o) { return int(o.retinal.target); };
  e.set = [](SolverOptions& o, int i) { o.retinal.target = RetinalTarget(i); };
  add();
  e.key = "eyebox_range", e.kind = Kind::kReal, e.type = "length", e.dimension = Dimension::kLength;
  e.has_range = true, e.range = Closed(0, kMaxEyeboxRange), e.constraint_note = " m (0 = the eye's pupil alone)";
  e.default_text = "0 m (the eye's pupil alone)";
  e.meaning =
      "the retinal objective over an eyebox of pupils: a square grid of pupil positions within this of the eye's, "
      "in x and y (docs/eye-pose.md)";
  e.cli_flag = "--eyebox-range";
  e.cli_help = "Weigh the pupil positions within this of the eye's (retinal objective): m, or with units (\"1 mm\")";
  e.python = "eyebox_range", e.real = &SolverOptions::eyebox_range_m;
  add();
  e.key = "eyebox_step", e.kind = Kind::kReal, e.type = "length", e.dimension = Dimension::kLength;
  e.has_range = true, e.range = Closed(0, kMaxEyeboxRange), e.constraint_note = " m (0 = eyebox_range)";
  e.default_text = "eyebox_range (3 x 3 positions)";
  e.meaning = "the eyebox grid's spacing";
  e.cli_flag = "--eyebox-step", e.cli_help = "The eyebox grid's spacing: m, or with units (default: the range)";
  e.python = "eyebox_step", e.real = &SolverOptions::eyebox_step_m;
  add();
  e.key = "eyebox_sigma", e.kind = Kind::kReal, e.type = "length", e.dimension = Dimension::kLength;
  e.has_range = true, e.range = Closed(0, 1), e.constraint_note = " m (0 = uniform)";
  e.default_text = "0 m (uniform)";
  e.meaning = "the eyebox grid's weights: a Gaussian of this standard deviation about the eye's pupil";
  e.cli_flag = "--eyebox-sigma", e.cli_help = "The eyebox grid's weights, a Gaussian of this width (default: uniform)";
  e.python = "eyebox_sigma", e.real = &SolverOptions::eyebox_sigma_m;
  add();

  e.key = "panel_diffraction", e.kind = Kind::kBoolean, e.type = "boolean", e.default_text = "false";
  e.meaning =
      "solve through the panels' diffraction: the forward model sees each layer through the pixel grids of the "
      "panels in front (fill_factor below 1; joint, multiplicative, quasi-newton; docs/optics.md)";
  e.cli_flag = "--panel-diffraction";
  e.cli_help = "Solve through the panels' diffraction (fill_factor below 1; joint, multiplicative, quasi-newton)";
  e.python = "panel_diffraction";
  e.get = [](const SolverOptions& o) { return int(o.panel_diffraction); };
  e.set = [](SolverOptions& o, int i) { o.panel_diffraction = i != 0; };
  add();
  e.key = "lc_response", e.kind = Kind::kBoolean, e.type = "boolean", e.default_text = "false";
  e.meaning =
      "solve through the panels' liquid-crystal response: the forward model is the frame's time average of what "
      "the panels show as they relax between subframes (rise_time, fall_time; quasi-newton; "
      "docs/time-multiplexing.md)";
  e.cli_flag = "--lc-response";
  e.cli_help = "Solve through the panels' LC response (rise_time, fall_time; quasi-newton)";
  e.python = "lc_response";
  e.get = [](const SolverOptions& o) { return int(o.lc_response); };
  e.set = [](SolverOptions& o, int i) { o.lc_response = i != 0; };
  add();

  // Not in the scene file.
  e.key = "epsilon", e.kind = Kind::kReal, e.type = "number", e.in_scene = false, e.has_range = true;
  e.range = {0, 1e-3, true, true}, e.default_text = "1e-12";
  e.meaning = "multiplicative updates: denominators below this keep the pixel as is";
  e.python = "epsilon", e.real = &SolverOptions::epsilon;
  add();
  e.key = "floor", e.kind = Kind::kReal, e.type = "number", e.in_scene = false, e.has_range = true;
  e.range = {0, 0.1, true, true}, e.constraint_note = ": a zero transmittance never recovers";
  e.default_text = "1e-6", e.meaning = "multiplicative updates: the lowest transmittance";
  e.python = "floor", e.real = &SolverOptions::floor;
  add();
  e.key = "measure_focal_stack", e.kind = Kind::kBoolean, e.type = "boolean", e.in_scene = false;
  e.default_text = "false";
  e.meaning = "with the light-field objective: also the focal-stack PSNR of every trace row, off the clock";
  e.cli_flag = "--measure-focal-stack";
  e.cli_help = "Also record the focal stack's PSNR in the trace, off the clock (the retinal objective records it)";
  e.get = [](const SolverOptions& o) { return int(o.measure_focal_stack); };
  e.set = [](SolverOptions& o, int i) { o.measure_focal_stack = i != 0; };
  add();
  return t;
}

}  // namespace

const std::vector<SolverOptionEntry>& SolverOptionTable() {
  static const std::vector<SolverOptionEntry> table = MakeTable();
  return table;
}

const SolverOptionEntry* FindSolverOption(const std::string& key) { return FindOption(SolverOptionTable(), key); }

std::string SolverOptionProblem(const std::string& key, double value, const std::string& name) {
  const SolverOptionEntry& e = *FindSolverOption(key);
  return !e.has_range || e.range.Contains(value) ? "" : OptionViolation(name, value, e.Constraint());
}

}  // namespace layerlab
