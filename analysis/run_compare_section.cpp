// The run's comparison (run.compare): this display and the others it names,
// each with its solvers and objectives, on the same target, into OUT/compare.
#include "layerlab/analysis/compare.h"
#include "layerlab/analysis/report_parts.h"
#include "layerlab/analysis/run_steps.h"
#include "layerlab/framework/error.h"
#include "layerlab/solvers/solve_config.h"

namespace layerlab {
namespace {

// One display of the comparison: its name, system and "solve" section.
struct ComparedDisplay {
  const std::string& name;
  const DisplaySystem& system;
  const SolveConfig& config;
  bool own_options;  // its scene's own "solve" section (ReadRunInputs)
};

// The main solve already ran `run` on the main display: its trace, cut at the
// budget, is the row; false when it did not or its trace ends before the budget.
bool MainSolveRow(const RunState& s, const ComparedDisplay& d, const CompareRun& run,
                  std::vector<CompareResult>* rows) {
  const CompareRunConfig& c = s.in.run.compare;
  const SolverOptions& main = s.in.solve.options;
  if (&d.system != &s.in.system || run.solver != s.in.solve.solver || c.iterations ||
      run.options.objective != main.objective || (run.options.measure_focal_stack && !main.measure_focal_stack) ||
      (!run.options.measure_metrics.empty() &&
       (run.options.measure_metrics != main.measure_metrics || !(run.options.metric_settings == main.metric_settings))))
    return false;
  const std::optional<SolverReport> report = c.time_budget_s ? ReportWithTimeBudget(s.solved.report, *c.time_budget_s)
                                                             : std::optional<SolverReport>(s.solved.report);
  if (!report) return false;
  rows->push_back({d.name, run.solver, *report, d.system.brightness_efficiency, d.system.luminance_efficiency,
                   d.system.subframes, d.system.subframes * d.system.frame_rate_hz, "scene"});
  return true;
}

// The rows of one display and solver: one per objective compared.
void RowsOf(RunState& s, const ComparedDisplay& d, const std::string& solver, std::vector<CompareResult>* rows) {
  const CompareRunConfig& c = s.in.run.compare;
  if (std::string why = CompareRefusal(solver, d.system, d.config.options); !why.empty()) {
    s.page.warnings.push_back("compare: skipped " + d.name + " / " + solver + ": the solver " + why);
    return;
  }
  const bool own = solver == d.config.solver && d.own_options;
  SolverOptions base = solver == d.config.solver ? d.config.options : SolverRegistry::Builtins().find(solver)->defaults;
  base.iterations = c.iterations.value_or(base.iterations);
  base.time_budget = c.time_budget_s.value_or(base.time_budget);
  base.panel_diffraction = d.config.options.panel_diffraction;  // the display's physics: every row's
  base.lc_response = d.config.options.lc_response;
  base.metric_settings = c.metric_settings;
  std::vector<std::string> skipped;
  const std::vector<CompareRun> runs =
      ObjectiveRuns({d.name, d.system, solver, base, d.config.sampling, own ? "scene" : "shared"}, c.objectives,
                    &skipped, SolverRegistry::Builtins(), c.metrics);
  for (const std::string& line : skipped) s.page.warnings.push_back("compare: skipped " + line);
  for (const CompareRun& run : runs) {
    s.outcome.compare_scenes.push_back(d.system.file);
    if (MainSolveRow(s, d, run, rows)) continue;
    if (s.target->rendered && s.target->moved_m != TargetSceneMove(d.system.eye))
      throw Error("compare: " + d.name +
                  " sees the target scene from elsewhere than this display (an eye of a binocular pair with a "
                  "display of its own sees it from its own axis): compare displays seen by the same eye");
    CompareRun attached = run;
    AttachRetinalTarget(*s.target, &attached.options);
    CompareResult result = RunComparison({attached}, s.target->light_field, true).front();
    if (!result.report.IsSolutionUsable())
      throw Error("compare: " + RunLabel(result) + " failed: " + result.report.message);
    rows->push_back(std::move(result));
  }
}

std::string RunCompare(RunState& s) {
  const CompareRunConfig& c = s.in.run.compare;
  std::vector<ComparedDisplay> displays = {{s.in.name, s.in.system, s.in.solve, true}};
  for (const OtherDisplay& d : s.in.compare) displays.push_back({d.name, d.system, d.config, d.own_options});
  std::vector<CompareResult> rows;
  for (const ComparedDisplay& d : displays)
    for (const std::string& solver : c.solvers.empty() ? std::vector<std::string>{d.config.solver} : c.solvers)
      RowsOf(s, d, solver, &rows);
  AddCompareToPage(rows, (s.out / "compare").string(), "compare/", &s.page);
  s.outcome.compare_table = CompareTable(rows);
  s.outcome.compare = rows;
  return "compare (" + std::to_string(rows.size()) + " runs)";
}

}  // namespace

RunSection CompareRunSection() {
  return {"compare", [](const RunInputs& in) { return in.run.compare.enabled; }, RunCompare};
}

}  // namespace layerlab
