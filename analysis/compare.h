// Several displays and solvers on one target: error against wall time for
// each run, and what each display costs in brightness.
#pragma once

#include <array>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "layerlab/solvers/solver.h"
#include "layerlab/systems/display_system.h"

namespace layerlab {

struct TraceColumn;  // solvers/trace_columns.h

struct CompareRun {
  std::string display;  // a name for the scene
  DisplaySystem system;
  std::string solver;
  SolverOptions options;
  Sampling sampling = Sampling::kNearest;
  // Where the options come from, for the table: "shared" (the same for every
  // row: the solver's defaults and the command's overrides) or "scene" (the
  // scene's own "solve" section).
  std::string options_from = "shared";
};

// A solution's eyebox (analysis/eyebox_map.h): the run of pupil positions
// through the centre, along x and y, whose retinal PSNR stays within the
// quality of the centre's.
struct EyeboxExtent {
  std::array<double, 2> within_m{};    // m
  std::array<bool, 2> reaches_edge{};  // the run reaches the grid's edge: the eyebox is at least that
  double centre_psnr_db = 0;
};

// What RunComparison measures of each solution's eyebox: with an
// accommodation, the retinal PSNR against natural viewing of the target over
// the pupil positions, `step_m` apart, at which the whole pupil stays inside
// the light field's eyebox.
struct CompareEyebox {
  std::optional<double> accommodation_diopters;  // none: not measured
  double step_m = 0.5e-3;
  double quality_db = 1.0;
};

struct CompareResult {
  std::string display, solver;
  SolverReport report;
  Rgb brightness_efficiency{};  // light at the eye per light emitted, per channel
  double luminance_efficiency = 0;
  int subframes = 1;                                  // patterns per panel and frame (time multiplexing)
  double panel_refresh_hz = 60;                       // what the panels must show: subframes x frame rate
  std::string options_from = "shared";                // CompareRun::options_from
  std::optional<EyeboxExtent> eyebox = std::nullopt;  // with CompareEyebox::accommodation_diopters
};

// The focal stack's perceptual columns (solvers/trace_columns.h) that some run measured, in the table's order.
std::vector<const TraceColumn*> MeasuredMetricColumns(const std::vector<CompareResult>& results);
// A column's value in the report's last row: NaN when that row did not measure it.
double FinalTraceValue(const TraceColumn& column, const SolverReport& report);
// "SSIM", "MS-SSIM", "JND": a metric column's heading.
std::string MetricHeading(const TraceColumn& column);

// "DISPLAY / SOLVER", and " / retinal" for a solve of the retinal objective.
std::string RunLabel(const std::string& display, const std::string& solver, ObjectiveKind objective);
std::string RunLabel(const CompareResult& result);

// The focal-stack PSNR of a run's last trace row (mean over states, dB), or
// NaN when the run did not measure it.
double FinalFocalStackPsnr(const SolverReport& report);

// Every solver of `registry` that suits `system` (SolverType::unsuitable), by name.
std::vector<std::string> SuitableSolvers(const DisplaySystem& system,
                                         const SolverRegistry& registry = SolverRegistry::Builtins());

// What to run of each scene: `solvers` by name, {"all"} for every one that
// suits the display, none for the scene's own; `iterations` and
// `time_budget` (s, 0: none) replace every run's. `objectives`: each
// display and solver runs once per objective the solver minimizes (none:
// the light-field objective, or the scene's own with scene_options); when
// one of them is the retinal objective, the light-field runs measure the
// focal stack too (off the clock), so that every row has both PSNRs. Like for like unless
// `scene_options`: every row runs its solver with that solver's defaults
// (nearest sampling); with it, a scene's own solver runs with its "solve"
// section's options and sampling (options_from "scene").
struct CompareSelection {
  std::vector<std::string> solvers;
  std::optional<int> iterations;
  std::optional<double> time_budget;
  bool scene_options = false;
  std::vector<ObjectiveKind> objectives;
  // The focal stack's metrics every run measures beside its PSNR (metrics/retinal_metrics.h): PSNR alone when
  // empty or psnr only; else every row measures the focal stack and these (SolverOptions::measure_metrics).
  std::vector<const RetinalMetric*> metrics;
  MetricSettings metric_settings;  // how they are measured (foveal weighting, the JND's exponent)
};

// The options of one run of `objectives` (CompareSelection::objectives): the
// objective set, and the focal stack measured when another run minimizes it.
SolverOptions WithObjective(SolverOptions options, ObjectiveKind objective,
                            const std::vector<ObjectiveKind>& objectives,
                            const std::vector<const RetinalMetric*>& metrics = {});

// `run` once per objective of `objectives` (none: its options' own) that its
// solver minimizes, WithObjective; a line in *skipped for each it does not
// ("NAME / SOLVER / retinal: the solver ...").
std::vector<CompareRun> ObjectiveRuns(const CompareRun& run, const std::vector<ObjectiveKind>& objectives,
                                      std::vector<std::string>* skipped,
                                      const SolverRegistry& registry = SolverRegistry::Builtins(),
                                      const std::vector<const RetinalMetric*>& metrics = {});

// The runs of `layerlab compare SCENES` (and of Python's compare()): each
// scene file compiled, named by its stem. A named solver that does not suit a
// display, or an objective it does not minimize, is left out with a line in
// *skipped ("NAME / SOLVER: the solver ...").
// Throws layerlab::Error for an unknown solver, a bad scene, or nothing to run.
// Where the runs' displays see a target scene given in a binocular pair's frame (TargetSceneMove, the same for
// every run); throws layerlab::Error naming two runs that see it from different places.
std::array<double, 3> CommonTargetMove(const std::vector<CompareRun>& runs);

// Why `solver` is left out of a comparison on `system` ("" when it is not), worded to follow "the solver": it
// does not suit the display, or the scene's solve (`physics`: its panel_diffraction and lc_response) asks for
// the panels' diffraction or response and it does not model them.
std::string CompareRefusal(const std::string& solver, const DisplaySystem& system, const SolverOptions& physics,
                           const SolverRegistry& registry = SolverRegistry::Builtins());

std::vector<CompareRun> CompareRunsOf(const std::vector<std::string>& scene_files, const CompareSelection& selection,
                                      std::vector<std::string>* skipped);

// What the comparison should say: each display's compile warnings and its
// target-geometry warnings once ("NAME: ..."), then each run's solver
// warnings ("NAME / SOLVER: ...").
std::vector<std::string> CompareWarnings(const std::vector<CompareRun>& runs, const std::vector<CompareResult>& results,
                                         const LightFieldGeometry& target);

// Runs each in turn on `target` (each display bound to the target's rays),
// the solvers taken from `registry`. With `show_progress`, one progress line
// per run on stderr (framework/progress.h; each iteration with --verbose).
std::vector<CompareResult> RunComparison(const std::vector<CompareRun>& runs, const LightField& target,
                                         bool show_progress = false,
                                         const SolverRegistry& registry = SolverRegistry::Builtins(),
                                         const CompareEyebox& eyebox = {});

std::string CompareTable(const std::vector<CompareResult>& results);  // fixed-width text
std::string CompareCsv(const std::vector<CompareResult>& results);    // one row per run
// compare.csv's rows for machines (`layerlab compare --json`): its columns as keys, null where not measured.
nlohmann::json CompareJson(const std::vector<CompareResult>& results);
std::string TracesCsv(const std::vector<CompareResult>& results);  // one row per run and iteration
// The light-field PSNR against wall time, and beside it the focal-stack PSNR
// when some run measured it.
std::string PsnrAgainstTimeSvg(const std::vector<CompareResult>& results);

}  // namespace layerlab
