// layerlab solve SCENE.json --target LF_DIR --solver NAME --out DIR: factorize
// a target light field (or a target scene, rendered first) into panel images,
// with progress on the terminal.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include "analysis/report_parts.h"
#include "analysis/target_source.h"
#include "app/command_line.h"
#include "app/commands.h"
#include "app/number_list.h"
#include "app/target_option.h"
#include "framework/interrupt.h"
#include "framework/lightfield_io.h"
#include "framework/progress.h"
#include "framework/staged_output.h"
#include "framework/warnings.h"
#include "solvers/memory_estimate.h"
#include "solvers/solution_writer.h"
#include "solvers/solve_config.h"
#include "solvers/solver_checkpoint.h"
#include "systems/compile.h"

namespace layerlab::app {

void AddSolveCommand(CLI::App& app) {
  struct Options {
    std::string scene, solver, out, sampling, target_range, objective;
    TargetOption target;
    std::optional<int> iterations, sub_iterations, warm_start_iterations, threads;
    std::optional<double> tolerance, initial_value;
    std::string time_budget;
    bool write_lightfield = false, resume = false, measure_focal_stack = false;
    int checkpoint_every = 0;
    std::string max_memory;
  };
  auto o = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand("solve", "Factorize a target light field into layer patterns");
  cmd->add_option("scene", o->scene, "Scene file (JSON); its \"solve\" section gives the defaults")->required();
  AddTargetOptions(cmd, o->target, " (default: the scene's solve section)");
  cmd->add_option("--solver", o->solver, "Solver: " + JoinWords(SolverRegistry::Builtins().names(), ", "));
  cmd->add_option("--out", o->out, "Output folder")->required();
  cmd->add_option("--iterations", o->iterations, "Outer iterations");
  cmd->add_option("--sub-iterations", o->sub_iterations, "Updates per set and outer iteration (hybrid)");
  cmd->add_option("--warm-start-iterations", o->warm_start_iterations,
                  "Iterations made by the hybrid solver before quasi-Newton steps (quasi-newton)");
  cmd->add_option("--time-budget", o->time_budget, "Stop after this long: seconds, or with units (\"5 s\", \"2 min\")");
  cmd->add_option("--tolerance", o->tolerance, "Stop when the objective changes by less than this, relative");
  cmd->add_option("--initial", o->initial_value, "Initial transmittance (negative: random)");
  cmd->add_option("--threads", o->threads, "Worker threads (0: all cores)");
  cmd->add_option("--sampling", o->sampling, "Layer sampling: nearest or bilinear");
  cmd->add_option("--target-range", o->target_range, "Target values beyond the display: clip or scale");
  cmd->add_option("--objective", o->objective,
                  "What is minimized: lightfield, or retinal (the focal stack; quasi-newton, joint)");
  cmd->add_flag("--measure-focal-stack", o->measure_focal_stack,
                "Also record the focal stack's PSNR in the trace, off the clock (the retinal objective records it)");
  cmd->add_flag("--write-lightfield", o->write_lightfield, "Also write the synthesized light field");
  cmd->add_option("--checkpoint-every", o->checkpoint_every,
                  "Write OUT/checkpoint every N iterations (and when stopped early)");
  cmd->add_flag("--resume", o->resume, "Continue from OUT/checkpoint (same scene, target and solver)");
  cmd->add_option("--max-memory", o->max_memory,
                  "Refuse a run estimated to need more (e.g. 2 GB; default: the machine's memory)");
  cmd->callback([o] {
    Scene scene = LoadScene(o->scene);
    DisplaySystem system = Compile(scene);
    SolveConfig config = ReadSolveConfig(scene, system);
    if (!o->solver.empty() && o->solver != config.solver) {
      config.solver = o->solver;
      SolverRegistry::Builtins().create(o->solver);  // names the known ones if unknown
      config.options = SolverRegistry::Builtins().find(o->solver)->defaults;
    }
    SolverOptions& opt = config.options;
    ApplyTargetOption(o->target, config);
    RequireTarget(config, o->scene);
    // Any value given is checked by SolverOptions.
    opt.iterations = o->iterations.value_or(opt.iterations);
    opt.sub_iterations = o->sub_iterations.value_or(opt.sub_iterations);
    opt.warm_start_iterations = o->warm_start_iterations.value_or(opt.warm_start_iterations);
    if (!o->time_budget.empty()) opt.time_budget = ParseOptionValue(o->time_budget, "--time-budget", kSeconds);
    opt.tolerance = o->tolerance.value_or(opt.tolerance);
    opt.initial_value = o->initial_value.value_or(opt.initial_value);
    opt.threads = o->threads.value_or(opt.threads);
    if (!o->sampling.empty()) config.sampling = SamplingFromString(o->sampling);
    if (!o->target_range.empty()) {
      if (o->target_range != "clip" && o->target_range != "scale")
        throw Error("--target-range: \"" + o->target_range + "\" is not one of clip or scale");
      opt.target_range = o->target_range == "clip" ? TargetRange::kClip : TargetRange::kScale;
    }
    if (!o->objective.empty()) {
      if (o->objective != "lightfield" && o->objective != "retinal")
        throw Error("--objective: \"" + o->objective + "\" is not one of lightfield or retinal");
      opt.objective = o->objective == "retinal" ? ObjectiveKind::kRetinal : ObjectiveKind::kLightField;
    }
    if (const std::string why = ObjectiveRefusal(config.solver, opt.objective); !why.empty())
      throw Error("--objective " + ToString(opt.objective) + ": " + why);
    opt.measure_focal_stack = o->measure_focal_stack;

    // Refuse what cannot fit before reading the views or rendering the target.
    const size_t limit = o->max_memory.empty() ? 0 : ParseByteSize(o->max_memory, "--max-memory");
    const size_t need =
        RefuseSolveBeyondMemory(system, config, opt.threads, limit, "--max-memory " + FormatBytes(double(limit)));
    Note("the solve needs about " + FormatBytes(double(need)));
    // The results are built beside the earlier ones and switched into place when complete.
    StagedOutput stage(
        o->out, "solve",
        {"patterns", "panels", "lightfield", "trace.csv", "report.txt", "report.json", "checkpoint", "index.html",
         "pattern_previews", "panel_previews", "psnr_vs_time.svg"},
        {{o->scene, "the scene"}, {config.target, "the target"}, {config.target_scene, "the target scene"}});
    for (const std::string& line : stage.recovered()) Note("solve: " + line);
    std::unique_ptr<Target> target = LoadOrRenderTarget(config, "target");
    DisplayModel model(system, target->light_field.geometry, config.sampling);
    InstallInterruptHandler();
    opt.interrupted = Interrupted;
    const std::string checkpoint_folder = (std::filesystem::path(o->out) / "checkpoint").string();
    if (o->checkpoint_every < 0) throw Error("--checkpoint-every: must be 0 (none) or positive");
    opt.checkpoint_every = o->checkpoint_every;
    // Hashing the target costs a pass over it: only when a checkpoint is written or read.
    const CheckpointInputs digest =
        o->checkpoint_every > 0 || o->resume
            ? CheckpointDigest(model, config.sampling, target->light_field, config.solver, opt)
            : CheckpointInputs{};
    if (o->checkpoint_every > 0)
      opt.checkpoint = [&](const SolverCheckpoint& c) { WriteCheckpoint(model, c, checkpoint_folder, digest); };
    std::optional<SolverCheckpoint> resume;
    if (o->resume) {
      RefuseMismatchedCheckpoint(checkpoint_folder, digest);
      resume = ReadCheckpoint(model, checkpoint_folder);
      opt.resume = &*resume;
      Note("resuming " + resume->solver + " from iteration " + std::to_string(resume->iteration));
    }
    Patterns patterns;
    SolverReport report;
    {
      Progress progress(config.solver, opt.iterations);
      opt.progress = [&](const IterationRecord& row) {
        char detail[64];
        std::snprintf(detail, sizeof detail, "iterations  PSNR %.2f dB", row.psnr_db);
        progress.Update(row.iteration, detail);
      };
      report = SolverRegistry::Builtins().create(config.solver)->Solve(model, target->light_field, opt, &patterns);
      progress.Finish(ToString(report.termination));
    }
    std::vector<std::string> found = system.warnings;  // the compile's and the target's first
    for (const std::string& w : TargetGeometryWarnings(system, target->light_field.geometry)) found.push_back(w);
    report.warnings.insert(report.warnings.begin(), found.begin(), found.end());
    SayWarnings(report.warnings);
    std::cout << report.BriefReport() << "\n";
    if (!report.IsSolutionUsable()) throw Error("the solve failed: " + report.message + "; nothing was written");
    try {
      WriteSolution(model, patterns, report, stage.staging(), {.write_lightfield = o->write_lightfield});
      RunReportPage page = CommandPage(
          "solve", o->scene, scene.name.empty() ? std::filesystem::path(o->scene).stem().string() : scene.name,
          scene.description, CommandLine());
      page.system = &system;
      page.steps = {
          {"solve (" + config.solver + ", " + std::to_string(report.iterations) + " iterations)", report.seconds}};
      page.warnings = report.warnings;
      AddSolveToPage(system, patterns, report, stage.staging(), "", o->write_lightfield, &page);
      WriteReportPage(page, stage.staging());
    } catch (const Error& e) {
      throw stage.Explain(e);
    }
    const StagedOutput::Switched switched = stage.Commit();
    if (!switched.removed.empty())
      std::fprintf(stderr, "solve: removed %zu file%s an earlier solve wrote into %s\n", switched.removed.size(),
                   switched.removed.size() == 1 ? "" : "s", o->out.c_str());
    std::cout << "wrote " << o->out << "/{index.html,patterns,panels,trace.csv,report.txt,report.json"
              << (o->write_lightfield ? ",lightfield" : "") << "}\n";
    if (report.termination == Termination::kInterrupted)
      throw InterruptedError("interrupted: " + o->out + " holds the patterns of iteration " +
                             std::to_string(report.iterations) + ", the last complete one");
  });
}

}  // namespace layerlab::app
