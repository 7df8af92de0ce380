// layerlab optimize DESIGN.json --out DIR: the display's design itself
// optimized (design/design_spec.h, docs/optimize.md). Checks the design and
// its constraints before anything runs, evaluates designs (each a `layerlab
// run` of the scene with the values written in) as NLopt asks for them,
// and writes the best scene, the history and the report. A run again into
// the same folder resumes: the evaluations in its log are not repeated.
#include <cstdio>
#include <memory>
#include <string>

#include "layerlab/app/command_result.h"
#include "layerlab/app/commands.h"
#include "layerlab/design/design_report.h"
#include "layerlab/design/design_search.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/interrupt.h"
#include "layerlab/framework/progress.h"

namespace layerlab::app {
namespace {

struct OptimizeOptions {
  std::string design, out;
  int evaluations = 0;  // 0: the design file's
};

std::string Value(const DesignVariable& v, double x) { return FormatGeneral(x) + (v.unit.empty() ? "" : " " + v.unit); }

void RunOptimizeCommand(const OptimizeOptions& o) {
  DesignSpec spec = ReadDesignSpec(o.design);
  if (o.evaluations > 0) spec.optimizer.evaluations = o.evaluations;
  CheckDesignFeasible(spec);
  InstallInterruptHandler();
  DesignEvaluator evaluator(spec, o.out);
  const FileLock lock = LockSweepFolder(evaluator.sweep(), o.out);
  if (const size_t earlier = evaluator.Resume())
    Note("optimize: " + std::to_string(earlier) + " evaluations in " + o.out +
         "/evaluations.jsonl from an earlier run; they are not repeated");
  DesignSearch search;
  try {
    search = SearchDesign(spec, &evaluator);
  } catch (const InterruptedError&) {
    throw InterruptedError(
        "optimize: interrupted; the finished evaluations are kept, run the same command again "
        "to resume");
  }
  const DesignEvaluation* best = BestFeasible(spec, evaluator);
  const std::vector<std::string> written = WriteDesignReport(spec, evaluator, search, best, o.out);

  CommandResult result("optimize");
  const size_t n = evaluator.evaluations().size();
  const double per_minute = search.seconds > 0 ? 60.0 * static_cast<double>(evaluator.ran()) / search.seconds : 0;
  result.Text("optimize: " + std::to_string(n) + " evaluations (" + std::to_string(evaluator.ran()) + " run here, " +
              std::to_string(evaluator.replayed()) + " from the log) in " + FormatFixed(search.seconds, 1) + " s (" +
              FormatFixed(per_minute, 1) + " per minute); stopped because " + search.stopped + "\n");
  result["out"] = o.out;
  result["evaluations"] = n;
  result["ran"] = evaluator.ran();
  result["replayed"] = evaluator.replayed();
  result["seconds"] = search.seconds;
  result["evaluations_per_minute"] = per_minute;
  result["stopped"] = search.stopped;
  result["report"] = o.out + "/report.html";
  if (!best) {
    result.Print();
    const DesignEvaluation* ran = nullptr;
    for (const DesignEvaluation* e : evaluator.evaluations())
      if (!e->failed) ran = e;
    if (!ran) {
      const auto all = evaluator.evaluations();
      throw Error(o.design + ": every evaluation failed" +
                  (all.empty() ? std::string() : "; the first (" + all.front()->id + "): " + all.front()->error));
    }
    std::string names;
    for (const std::string& name : UnmetConstraints(spec, evaluator))
      names += (names.empty() ? "\"" : ", \"") + name + "\"";
    throw Error(o.design + ": no evaluated design met the constraints; the closest missed " + names + " (see " + o.out +
                "/history.csv)");
  }
  std::string values;
  nlohmann::json best_values = nlohmann::json::object();
  for (size_t k = 0; k < spec.variables.size(); ++k) {
    values += (k ? ", " : "") + spec.variables[k].name + " " + Value(spec.variables[k], best->x[k]);
    best_values[spec.variables[k].column()] = best->x[k];
  }
  const DesignMetric& first = spec.metrics[spec.objective[0].metric];
  result.Text("optimize: best design " + best->id + ": " + values + "; " + spec.objective_column() + " " +
              FormatGeneral(ShownObjective(spec, *best)) + "\n");
  result.Text("optimize: wrote " + o.out + "/best_scene.json and " + o.out + "/report.html\n");
  result["best"] = best_values;
  result["best_evaluation"] = best->id;
  result["objective_column"] = spec.objective_column();
  result["objective"] = ShownObjective(spec, *best);
  result["higher_is_better"] = spec.objective.size() == 1 && first.higher_is_better;
  result["best_scene"] = o.out + "/best_scene.json";
  result["written"] = written;
  result.Print();
}

}  // namespace

void AddOptimizeCommand(CLI::App& app) {
  auto o = std::make_shared<OptimizeOptions>();
  CLI::App* cmd = app.add_subcommand(
      "optimize",
      "Optimize the display's design: the scene values a design file names (layer depths, focal lengths, split "
      "ratios), within bounds and constraints, for an objective (PSNR, accommodation support, brightness); each "
      "evaluation a run of the scene (docs/optimize.md)");
  cmd->add_option("design", o->design, "Design file (JSON, layerlab-design/1)")->required();
  cmd->add_option("--out", o->out,
                  "Output folder: jobs/, evaluations.jsonl, history.csv, best_scene.json, convergence.svg, "
                  "surface.svg, report.html; a run again into it resumes")
      ->required();
  cmd->add_option("--evaluations", o->evaluations, "The budget in evaluations (default: the design file's)")
      ->check(CLI::Range(1, 100000));
  cmd->callback([o] { RunOptimizeCommand(*o); });
}

}  // namespace layerlab::app
