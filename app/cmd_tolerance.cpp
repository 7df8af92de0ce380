// layerlab tolerance SCENE.json --out DIR [--samples N] [--seed S] [--tolerances FILE]:
// Monte Carlo over assembly tolerances (analysis/tolerance.h): each layer's
// misregistration in panel pixels, its distortion at the field edge and the
// PSNR of the nominal factorization shown on the perturbed display; a
// sensitivity pass that names the dominant tolerance; every sample as CSV.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "layerlab/analysis/solve_job.h"
#include "layerlab/analysis/tolerance.h"
#include "layerlab/analysis/tolerance_report.h"
#include "layerlab/app/command_line.h"
#include "layerlab/app/command_result.h"
#include "layerlab/app/commands.h"
#include "layerlab/app/target_option.h"
#include "layerlab/framework/atomic_file.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/json_file.h"
#include "layerlab/framework/progress.h"
#include "layerlab/framework/staged_output.h"
#include "layerlab/solvers/solver_option_table.h"
#include "layerlab/systems/compile.h"

namespace layerlab::app {
namespace {

struct ToleranceCommandOptions {
  std::string scene, out, tolerances;
  TargetOption target;
  int samples = 20, iterations = 5, view_stride = 0;
  uint64_t seed = 1;
  bool no_psnr = false;
};

ToleranceSpec SpecOf(const ToleranceCommandOptions& o, const Scene& scene) {
  if (!o.tolerances.empty()) return ReadToleranceFile(o.tolerances);
  if (!scene.document.contains("tolerance"))
    throw Error(o.scene +
                ": no tolerances: give --tolerances FILE or a \"tolerance\" object in the scene "
                "(\"tolerance\": {\"panel_decentre\": \"0.05 mm\", \"gap\": \"0.1 mm\", ...})");
  return ReadToleranceSpec(scene.document["tolerance"], Location{o.scene, "/tolerance"});
}

// The nominal factorization (a few iterations of the scene's solve) and the views it is scored on.
std::unique_ptr<ToleranceProbe> MakeProbe(const ToleranceCommandOptions& o, const Scene& scene,
                                          const DisplaySystem& nominal, std::string* note) {
  if (o.no_psnr) {
    *note = "PSNR not measured (--no-psnr).";
    return nullptr;
  }
  SolveJob job;
  job.system = &nominal;
  job.config = SolveJobConfig(scene, nominal);
  ApplyTargetOption(o.target, job.config);
  if (job.config.target.empty() && job.config.target_scene.empty()) {
    *note = "PSNR not measured: the scene's solve section names no target; give --target DIR.";
    return nullptr;
  }
  job.config.options.iterations = o.iterations;
  job.progress_label = "nominal solve (" + job.config.solver + ")";
  const std::unique_ptr<Target> target = LoadOrRenderTarget(job.config, "target");
  const SolvedJob solved = RunSolveJob(job, target->light_field, target.get());
  if (!solved.report.IsSolutionUsable()) throw Error("the nominal solve failed: " + solved.report.message);
  auto probe = std::make_unique<ToleranceProbe>(nominal, solved.patterns, target->light_field, o.view_stride,
                                                job.config.sampling);
  const LightFieldGeometry& g = probe->geometry();
  *note = "PSNR: the nominal factorization (" + job.config.solver + ", " + std::to_string(o.iterations) +
          " iterations on " + DescribeTarget(*target) + ") shown on each display, against " +
          std::to_string(g.views_x) + " x " + std::to_string(g.views_y) + " of the target's views (--view-stride).";
  return probe;
}

void RunToleranceCommand(const ToleranceCommandOptions& o) {
  if (o.samples < 1 || o.samples > 100000) throw Error("--samples: 1 to 100000, got " + std::to_string(o.samples));
  if (const std::string why = SolverOptionProblem("iterations", o.iterations, "--iterations"); !why.empty())
    throw Error(why);
  const Scene scene = LoadScene(o.scene);
  const DisplaySystem designed = Compile(scene);
  const ToleranceSpec spec = SpecOf(o, scene);
  const ToleranceModel model(scene, designed, spec);
  const DisplaySystem nominal = model.Compile(model.Zero());
  StagedOutput stage(o.out, "tolerance",
                     {"tolerance.md", "tolerance.json", "samples.csv", "draws.csv", "sensitivity.csv"},
                     {{o.scene, "the scene"}, {o.tolerances, "the tolerances"}, {o.target.target, "the target"}});
  try {
    std::string psnr_note;
    const std::unique_ptr<ToleranceProbe> probe = MakeProbe(o, scene, nominal, &psnr_note);
    ToleranceRunOptions options{o.samples, o.seed};
    std::optional<Progress> progress;
    const ToleranceRun run =
        RunTolerance(model, nominal, options, probe.get(), [&](size_t done, size_t total, const std::string& what) {
          if (!progress) progress.emplace("tolerance", total);
          progress->Update(done, what);
        });
    progress->Finish(std::to_string(run.samples.size()) + " samples, " + std::to_string(run.sensitivity.size()) +
                     " tolerances alone at their limits");
    const ToleranceReportInput in{scene.file, CommandLine(), &model, &run, o.seed, psnr_note};
    const std::string summary = ToleranceMarkdown(in);
    WriteFileAtomically(stage.staging() + "/tolerance.md", summary);
    const nlohmann::json json = ToleranceJson(in);
    WriteFileAtomically(stage.staging() + "/tolerance.json", json.dump(2) + "\n");
    WriteToleranceCsv(in, stage.staging());
    stage.Commit();
    CommandResult result("tolerance");
    result.Text(summary + "\nwrote " + o.out +
                "/{tolerance.md,tolerance.json,samples.csv,draws.csv,sensitivity.csv}\n");
    result["out"] = o.out;
    result["tolerance"] = json;  // tolerance.json
    result.Print();
  } catch (const Error& e) {
    throw stage.Explain(e);
  }
}

}  // namespace

void AddToleranceCommand(CLI::App& app) {
  auto o = std::make_shared<ToleranceCommandOptions>();
  CLI::App* cmd = app.add_subcommand("tolerance",
                                     "Monte Carlo over assembly tolerances: misregistration, "
                                     "distortion and PSNR per layer, the dominant tolerance");
  cmd->add_option("scene", o->scene, "Display scene file (JSON)")->required();
  cmd->add_option("--out", o->out, "Output folder")->required();
  cmd->add_option("--samples", o->samples, "Monte Carlo samples (default 20)");
  cmd->add_option("--seed", o->seed, "Seed of the draws (default 1): the same seed, the same numbers");
  cmd->add_option("--tolerances", o->tolerances, "A JSON file of tolerances (default: the scene's \"tolerance\")");
  AddTargetOptions(cmd, o->target, ": the target of the nominal solve the PSNR is measured with");
  cmd->add_option("--iterations", o->iterations, "Iterations of the nominal solve (default 5)");
  cmd->add_option("--view-stride", o->view_stride,
                  "Score the PSNR on every N-th view row and column of the target (default: about 3 x 3)");
  cmd->add_flag("--no-psnr", o->no_psnr, "Skip the solve and the PSNR");
  cmd->callback([o] { RunToleranceCommand(*o); });
}

}  // namespace layerlab::app
