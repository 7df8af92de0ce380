// layerlab run SCENE.json --out DIR: the main job (analysis/run_pipeline.h,
// docs/run-section.md). Does what the scene's "solve" and "run" sections
// declare, in order, and writes a report that opens without a server:
//
//   DIR/system.txt, system.json      the compiled system
//   DIR/target/                      the target's center view (and the rendered light field)
//   DIR/solve/                       patterns, panel-ready images, trace, report, PSNR plot
//   DIR/retina/                      retinal images over accommodation (display, natural)
//   DIR/contrast/                    the contrast sweep (CSV, peaks, SVG)
//   DIR/compare/                     other displays on the same target (table, CSV, SVG)
//   DIR/index.html                   the report
#include <chrono>
#include <memory>
#include <optional>
#include <string>

#include "layerlab/analysis/run_pipeline.h"
#include "layerlab/app/command_result.h"
#include "layerlab/app/commands.h"
#include "layerlab/framework/progress.h"
#include "layerlab/framework/units.h"
#include "layerlab/framework/warnings.h"
#include "layerlab/solvers/solution_writer.h"
#include "layerlab/solvers/solver_option_table.h"

namespace layerlab::app {

void AddRunCommand(CLI::App& app) {
  auto request = std::make_shared<RunRequest>();
  CLI::App* cmd = app.add_subcommand("run",
                                     "The main job: solve, retinal images, contrast and comparisons as the scene "
                                     "declares; a report in OUT/index.html");
  cmd->add_option("scene", request->scene,
                  "Scene file (JSON) with \"solve\" and \"run\" sections (docs/run-section.md)")
      ->required();
  cmd->add_option("--out", request->out, "Output folder")->required();
  // The main solve's, as `layerlab solve` takes them (the solver option table).
  for (const char* key : {"iterations", "threads"}) {
    const SolverOptionEntry& e = *FindSolverOption(key);
    cmd->add_option(e.cli_flag, key == std::string("iterations") ? request->iterations : request->threads,
                    e.cli_help + ", of the main solve (default: the scene's)");
  }
  cmd->callback([request] {
    const auto start = std::chrono::steady_clock::now();
    const RunOutcome outcome = RunPipeline(*request);
    SayWarnings(outcome.warnings);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (!outcome.removed.empty())
      Note("run: removed " + std::to_string(outcome.removed.size()) + " file" +
           (outcome.removed.size() == 1 ? "" : "s") + " an earlier run wrote into " + request->out);
    CommandResult result("run");
    result.Text(outcome.compare_table);
    if (outcome.solved) result.Text(outcome.report.BriefReport() + "\n");
    result.Text("run: " + FormatFixed(seconds, 1) + " s; open " + outcome.index_html +
                " in a browser (no server needed)\n");
    result["out"] = request->out;
    result["index_html"] = outcome.index_html;
    result["seconds"] = seconds;
    result["solve"] = outcome.solved ? ReportSummaryJson(outcome.report) : nlohmann::json(nullptr);
    result["warnings"] = outcome.warnings;
    result.Print();
  });
}

}  // namespace layerlab::app
