// layerlab compare SCENES... --target LF_DIR --out DIR: several displays and
// solvers on one target; a table (PSNR, seconds, iterations, brightness) and
// one plot of PSNR against wall time with every run on it, and OUT/index.html.
// Like for like: every row runs with the same solver options (each solver's
// defaults, --iterations, --time-budget) unless --scene-options asks for
// each scene's own "solve" section.
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>

#include "layerlab/analysis/compare.h"
#include "layerlab/analysis/report_parts.h"
#include "layerlab/analysis/target_source.h"
#include "layerlab/app/command_line.h"
#include "layerlab/app/command_result.h"
#include "layerlab/app/commands.h"
#include "layerlab/app/metric_flags.h"
#include "layerlab/app/number_list.h"
#include "layerlab/app/target_option.h"
#include "layerlab/framework/atomic_file.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/params.h"
#include "layerlab/framework/staged_output.h"
#include "layerlab/framework/warnings.h"
#include "layerlab/solvers/solve_config.h"
#include "layerlab/solvers/solver_option_table.h"

namespace layerlab::app {
namespace {

std::vector<std::string> SplitNames(const std::string& text) {
  std::vector<std::string> names;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ','))
    if (!item.empty()) names.push_back(item);
  return names;
}

}  // namespace

namespace {

struct CompareCommandOptions {
  std::vector<std::string> scenes;
  std::string out, solvers;
  TargetOption target;
  std::optional<int> iterations;
  std::string time_budget, objectives, metrics;
  bool scene_options = false;
  std::string eyebox_at, eyebox_step = "0.5", quality = "1";
  MetricFlags metric_flags;
};

// --eyebox-at and its step and quality: nothing measured without it.
CompareEyebox ReadCompareEyebox(const CompareCommandOptions& o) {
  CompareEyebox eyebox;
  if (o.eyebox_at.empty()) return eyebox;
  eyebox.accommodation_diopters = ParseOptionValue(o.eyebox_at, "--eyebox-at", kDiopters, true);
  eyebox.step_m = ParseOptionValue(o.eyebox_step, "--eyebox-step", kMillimeters) * 1e-3;
  if (!(eyebox.step_m > 0)) throw Error("--eyebox-step: must be above 0 mm");
  eyebox.quality_db = ParseOptionValue(o.quality, "--quality", {Dimension::kFraction, ""});
  if (!(eyebox.quality_db > 0)) throw Error("--quality: must be above 0 dB");
  return eyebox;
}

std::vector<ObjectiveKind> ParseObjectives(const std::string& names) {
  std::vector<ObjectiveKind> objectives;
  for (const std::string& name : SplitNames(names)) {
    const std::optional<ObjectiveKind> k = ObjectiveKindNamed(name);
    if (!k) throw Error("--objectives: \"" + name + "\" is not one of lightfield or retinal");
    objectives.push_back(*k);
  }
  return objectives;
}

// What to run: --solvers, --iterations, --time-budget, --scene-options, --objectives, --metrics, --fovea and
// --jnd-exponent.
CompareSelection ReadSelection(const CompareCommandOptions& o) {
  if (o.iterations)
    if (const std::string why = SolverOptionProblem("iterations", *o.iterations, "--iterations"); !why.empty())
      throw Error(why);
  std::optional<double> time_budget;
  if (!o.time_budget.empty()) time_budget = ParseOptionValue(o.time_budget, "--time-budget", kSeconds);
  const std::vector<const RetinalMetric*> metrics =
      o.metrics.empty() ? std::vector<const RetinalMetric*>{} : ParseRetinalMetrics(o.metrics, "--metrics");
  const MetricSettings settings = ParseMetricSettings(o.metric_flags);
  if (o.metric_flags.given() && metrics.empty())
    throw Error(o.metric_flags.named() + ": sets how the focal stack's metrics are measured: give --metrics");
  return {SplitNames(o.solvers),         o.iterations, time_budget, o.scene_options,
          ParseObjectives(o.objectives), metrics,      settings};
}

}  // namespace

void AddCompareCommand(CLI::App& app) {
  using Options = CompareCommandOptions;
  auto o = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand("compare", "Several displays and solvers on one target: PSNR against time");
  cmd->add_option("scenes", o->scenes, "Display scene files (JSON)")->required();
  AddTargetOptions(cmd, o->target, " (one of the two is required)");
  cmd->add_option("--out", o->out, "Output folder")->required();
  cmd->add_option("--solvers", o->solvers,
                  "Solvers to run on each display, comma-separated, or \"all\" for every solver that suits it "
                  "(default: each scene's own)");
  cmd->add_option("--iterations", o->iterations, "Iterations of every run (default: each solver's)");
  cmd->add_flag("--scene-options", o->scene_options,
                "Run each scene with its own \"solve\" section (options, sampling) instead of the same options for "
                "every row (each solver's defaults; the table's options column says which)");
  cmd->add_option("--time-budget", o->time_budget, "How long each run may take: seconds, or with units (\"5 s\")");
  cmd->add_option("--objectives", o->objectives,
                  "Objectives each solver runs, comma-separated: lightfield, retinal (the solvers that minimize it); "
                  "with retinal, every row also records the focal-stack PSNR (default: the light field's)");
  cmd->add_option("--metrics", o->metrics,
                  "Also measure the focal stack by these beside its PSNR, comma-separated: ssim, ms_ssim, jnd or all; "
                  "every row then measures the focal stack, off the clock, at iterations 0, 1, 2, 3, 5, 8, ... and "
                  "the last (docs/metrics.md)");
  AddMetricSettingFlags(cmd, &o->metric_flags);
  cmd->add_option("--eyebox-at", o->eyebox_at,
                  "Also each solution's eyebox, with the eye focused here (D): where its retinal PSNR stays within "
                  "--quality dB of the centre's, over the pupil positions inside the light field's eyebox");
  cmd->add_option("--eyebox-step", o->eyebox_step, "Their step: mm (default 0.5)");
  cmd->add_option("--quality", o->quality, "The eyebox's PSNR drop from its centre: dB (default 1)");
  cmd->callback([o] {
    const CompareEyebox eyebox = ReadCompareEyebox(*o);
    std::vector<std::string> skipped;
    std::vector<CompareRun> runs = CompareRunsOf(o->scenes, ReadSelection(*o), &skipped);
    for (const std::string& line : skipped) std::fprintf(stderr, "compare: skipped %s\n", line.c_str());
    SolveConfig target_config;
    ApplyTargetOption(o->target, target_config);
    target_config.target_moved_m = CommonTargetMove(runs);
    if (!o->target.given()) throw Error("compare: give the target: --target LF_DIR or --target-scene TARGET.json");
    std::vector<NamedInput> inputs = {{target_config.target, "the target"},
                                      {target_config.target_scene, "the target scene"}};
    for (const std::string& file : o->scenes) inputs.push_back({file, "a scene"});
    StagedOutput stage(o->out, "compare",
                       {"compare.txt", "compare.csv", "traces.csv", "psnr_vs_time.svg", "index.html"}, inputs);
    const std::unique_ptr<Target> target = LoadOrRenderTarget(target_config, "target");
    for (CompareRun& run : runs) AttachRetinalTarget(*target, &run.options);
    std::vector<CompareResult> results =
        RunComparison(runs, target->light_field, true, SolverRegistry::Builtins(), eyebox);
    for (const CompareResult& r : results)
      if (!r.report.IsSolutionUsable())
        throw Error("compare: " + RunLabel(r) + " failed: " + r.report.message + "; nothing was written");

    const std::vector<std::string> warnings = CompareWarnings(runs, results, target->light_field.geometry);
    SayWarnings(warnings);

    const std::string table = CompareTable(results);
    try {
      RunReportPage page = CommandPage("compare", JoinWords(o->scenes, ", "), "", "", CommandLine());
      for (const CompareResult& r : results) page.steps.push_back({RunLabel(r), r.report.seconds});
      AddCompareToPage(results, stage.staging(), "", &page);
      page.warnings = warnings;
      WriteReportPage(page, stage.staging());
      WriteFileAtomically(stage.staging() + "/compare.txt",
                          table + WarningLines(warnings));  // the table, then the warnings
    } catch (const Error& e) {
      throw stage.Explain(e);
    }
    stage.Commit();
    CommandResult result("compare");
    result.Text(table + "wrote " + o->out + "/{index.html,compare.txt,compare.csv,traces.csv,psnr_vs_time.svg}\n");
    result["out"] = o->out;
    result["runs"] = CompareJson(results);
    result["warnings"] = warnings;
    result.Print();
  });
}

}  // namespace layerlab::app
