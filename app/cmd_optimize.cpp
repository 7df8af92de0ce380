// layerlab optimize DESIGN.json --out DIR: the display's design itself
// optimized (design/design_spec.h, docs/optimize.md). Checks the design and
// its constraints before anything runs, evaluates designs (each a `layerlab
// run` of the scene with the values written in) as NLopt asks for them,
// and writes the best scene, the history and the report. A run again into
// the same folder resumes: the evaluations in its log are not repeated.
// A multistart's starts run in turn here, or in parallel: --local -j N,
// --mpi under mpirun, or --slurm's job array and its --gather step.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "layerlab/app/command_result.h"
#include "layerlab/app/commands.h"
#include "layerlab/app/optimize_runners.h"
#include "layerlab/design/design_report.h"
#include "layerlab/design/design_search.h"
#include "layerlab/design/design_starts.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/interrupt.h"
#include "layerlab/framework/params.h"
#include "layerlab/framework/progress.h"
#include "layerlab/framework/warnings.h"
#if LAYERLAB_WITH_MPI
#include "layerlab/framework/mpi_world.h"
#endif

namespace layerlab::app {
namespace {

struct OptimizeOptions {
  std::string design, out;
  int evaluations = 0;  // 0: the design file's
  int start = -1;       // --start K: that start alone
  bool local = false, mpi = false, slurm = false, gather = false;
  int processes = 0;
  SlurmResources slurm_resources;
};

std::string Value(const DesignVariable& v, double x) { return FormatGeneral(x) + (v.unit.empty() ? "" : " " + v.unit); }

// What the runners pass on to each start's process: the options that change the design.
std::vector<std::string> StartArguments(const OptimizeOptions& o) {
  if (o.evaluations > 0) return {"--evaluations", std::to_string(o.evaluations)};
  return {};
}

// The summary, the files and the exit: non-zero when no design met the constraints.
void Report(const DesignSpec& spec, const OptimizeOptions& o, const DesignEvaluator& scenes,
            const DesignHistory& history, const DesignSearch& search) {
  const DesignEvaluation* best = BestFeasible(spec, history.evaluations);
  const std::vector<std::string> written = WriteDesignReport(spec, scenes, history, search, best, o.out);

  CommandResult result("optimize");
  const size_t n = history.evaluations.size();
  const double per_minute = search.seconds > 0 ? 60.0 * static_cast<double>(history.ran) / search.seconds : 0;
  result.Text("optimize: " + std::to_string(n) + " evaluations (" + std::to_string(history.ran) + " run here, " +
              std::to_string(history.replayed) + " from the log) in " + FormatFixed(search.seconds, 1) + " s (" +
              FormatFixed(per_minute, 1) + " per minute); stopped because " + search.stopped + "\n");
  result["out"] = o.out;
  result["evaluations"] = n;
  result["ran"] = history.ran;
  result["replayed"] = history.replayed;
  result["seconds"] = search.seconds;
  result["evaluations_per_minute"] = per_minute;
  result["stopped"] = search.stopped;
  result["report"] = o.out + "/report.html";
  if (!best) {
    result.Print();
    const DesignEvaluation* ran = nullptr;
    for (const DesignEvaluation* e : history.evaluations)
      if (!e->failed) ran = e;
    if (!ran) {
      const auto& all = history.evaluations;
      throw Error(o.design + ": every evaluation failed" +
                  (all.empty() ? std::string() : "; the first (" + all.front()->id + "): " + all.front()->error));
    }
    std::string names;
    for (const std::string& name : UnmetConstraints(spec, history.evaluations))
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

void RunSingleSearch(const DesignSpec& spec, const OptimizeOptions& o) {
  DesignEvaluator evaluator(spec, o.out);
  const FileLock lock = LockSweepFolder(evaluator.sweep(), o.out);
  if (const size_t earlier = evaluator.Resume())
    Note("optimize: " + std::to_string(earlier) + " evaluations in " + evaluator.log_path() +
         " from an earlier run; they are not repeated");
  DesignSearch search;
  try {
    search = SearchDesign(spec, &evaluator);
  } catch (const InterruptedError&) {
    throw InterruptedError(
        "optimize: interrupted; the finished evaluations are kept, run the same command again "
        "to resume");
  }
  Report(spec, o, evaluator, {evaluator.evaluations(), evaluator.ran(), evaluator.replayed()}, search);
}

// --start K: one start, what a pool process, an MPI rank's turn and a Slurm task run.
void RunOneStart(const DesignSpec& spec, const OptimizeOptions& o) {
  const StartOutcome s = RunStart(spec, o.out, o.start);
  CommandResult result("optimize");
  result.Text("optimize: start " + StartId(o.start) + ": " + std::to_string(s.asked) + " evaluations (" +
              std::to_string(s.ran) + " run here, " + std::to_string(s.replayed) + " from the log) in " +
              FormatFixed(s.search.seconds, 1) + " s; stopped because " + s.search.stopped + "\n");
  result["start"] = StartId(o.start);
  result["evaluations"] = s.asked;
  result["ran"] = s.ran;
  result["replayed"] = s.replayed;
  result["seconds"] = s.search.seconds;
  result["stopped"] = s.search.stopped;
  result.Print();
}

// --slurm: the array's scripts, made (and so checked) before the folder is locked and they are written.
void WriteStartScripts(const DesignSpec& spec, const OptimizeOptions& o) {
  SlurmResources resources;
  resources.Override(o.slurm_resources);
  const SlurmScripts scripts =
      MakeSlurmScripts(OptimizeArrayCommand(spec, StartArguments(o)), spec.optimizer.starts, o.out, resources);
  DesignEvaluator scenes(spec, o.out);
  const FileLock lock = LockSweepFolder(scenes.sweep(), o.out);
  CommandResult result("optimize");
  result["out"] = o.out;
  result["starts"] = spec.optimizer.starts;
  const std::vector<std::string> written = WriteSlurmScripts(scripts);
  for (const std::string& script : written) result.Text("optimize: wrote " + script + "\n");
  result["slurm_scripts"] = written;
  result.Text("optimize: submit with sh " + o.out + "/slurm/submit.sh\n");
  result["submit"] = "sh " + o.out + "/slurm/submit.sh";
  result.Print();
}

// The starts in this process or a pool (not MPI's, not a gather): why they ended.
std::string RunStartsHere(const DesignSpec& spec, const OptimizeOptions& o) {
  const std::string starts = std::to_string(spec.optimizer.starts);
  if (o.local) {
    const int processes =
        o.processes > 0 ? o.processes : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
    const std::vector<std::string> failed = RunStartsLocally(spec, o.out, StartArguments(o), processes);
    if (!failed.empty())
      throw Error("optimize: " + std::to_string(failed.size()) + " of " + starts +
                  " starts did not end: " + JoinWords(failed, " and ") +
                  " (the finished evaluations are kept; run the same command again to resume)");
    return "each of its " + starts + " starts ended (" + std::to_string(processes) + " at a time)";
  }
  for (int k = 0; k < spec.optimizer.starts; ++k) {
    try {
      const StartOutcome s = RunStart(spec, o.out, k);
      Note("optimize: start " + StartId(k) + ": " + std::to_string(s.asked) + " evaluations; stopped because " +
           s.search.stopped);
    } catch (const InterruptedError&) {
      throw InterruptedError(
          "optimize: interrupted; the finished evaluations are kept, run the same command again to resume");
    }
  }
  return "each of its " + starts + " starts ended (one after another)";
}

void RunMultistart(const DesignSpec& spec, const OptimizeOptions& o) {
  if (o.start >= 0) return RunOneStart(spec, o);
  if (o.slurm) return WriteStartScripts(spec, o);
  const auto begun = std::chrono::steady_clock::now();
  DesignSearch search;
  size_t earlier = 0;  // the evaluations earlier runs left: those after the runners are this command's
  if (o.mpi) {
#if LAYERLAB_WITH_MPI
    bool root = false;
    earlier = RunStartsMpi(spec, o.out, &root);
    if (!root) return;
    search.stopped = "each of its " + std::to_string(spec.optimizer.starts) + " starts ended (on MPI ranks)";
#else
    throw Error(
        "--mpi: this layerlab was built without MPI (configure with -DLAYERLAB_WITH_MPI=ON; it needs "
        "OpenMPI: apt-get install libopenmpi-dev openmpi-bin)");
#endif
  }
  DesignEvaluator scenes(spec, o.out);
  const FileLock lock = LockSweepFolder(scenes.sweep(), o.out);
  if (!o.mpi) earlier = MultistartRecord(spec, o.out).evaluations().size();
  if (o.gather)
    search.stopped = "gathered from the starts' logs";
  else if (!o.mpi)
    search.stopped = RunStartsHere(spec, o);
  search.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - begun).count();
  const MultistartRecord record(spec, o.out);
  if (!record.missing().empty())
    SayWarnings({o.out + ": the starts " + JoinWords(record.missing(), " and ") +
                 " have no evaluations yet; the report shows the others"},
                "optimize: ");
  DesignHistory history;
  history.evaluations = record.evaluations();
  history.replayed = o.gather ? history.evaluations.size() : std::min(earlier, history.evaluations.size());
  history.ran = history.evaluations.size() - history.replayed;
  Report(spec, o, scenes, history, search);
}

void RunOptimizeCommand(const OptimizeOptions& o) {
  DesignSpec spec = ReadDesignSpec(o.design);
  if (o.evaluations > 0) {
    spec.optimizer.evaluations = o.evaluations;
    if (const std::string problem = BudgetProblem(spec.optimizer); !problem.empty())
      throw Error("--evaluations " + std::to_string(o.evaluations) + ": " + problem);
  }
  const bool runner = o.start >= 0 || o.local || o.mpi || o.slurm || o.gather;
  if (runner && spec.optimizer.global != "multistart")
    throw Error(Location{spec.file, "/optimizer/global"},
                std::string(o.start >= 0 ? "--start"
                            : o.local    ? "--local"
                            : o.mpi      ? "--mpi"
                            : o.slurm    ? "--slurm"
                                         : "--gather") +
                    " runs the starts of a multistart, and this design's global stage is \"" + spec.optimizer.global +
                    "\": set \"optimizer\": {\"global\": \"multistart\", \"starts\": N} to search from N starts "
                    "in parallel");
#if LAYERLAB_WITH_MPI
  if (o.mpi && !MpiWorld::Launched())
    throw Error("--mpi: this process was not started by an MPI launcher; run it as `mpirun -np N layerlab optimize " +
                o.design + " --out " + o.out + " --mpi`, or leave out --mpi to run the starts here (--local -j N)");
#endif
  CheckDesignFeasible(spec);
  InstallInterruptHandler();
  if (spec.optimizer.global == "multistart")
    RunMultistart(spec, o);
  else
    RunSingleSearch(spec, o);
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
                  "Output folder: jobs/, evaluations.jsonl (a multistart's starts/), history.csv, best_scene.json, "
                  "convergence.svg, surface.svg, report.html; a run again into it resumes")
      ->required();
  cmd->add_option("--evaluations", o->evaluations, "The budget in evaluations (default: the design file's)")
      ->check(CLI::Range(1, 100000));
  CLI::Option* start = cmd->add_option("--start", o->start,
                                       "A multistart: run only this start (its index), e.g. from a Slurm array task")
                           ->check(CLI::Range(0, 255));
  CLI::Option* local = cmd->add_flag(
      "--local", o->local, "A multistart: run the starts on this machine, a process pool (default: one after another)");
  cmd->add_option("-j,--jobs", o->processes, "With --local: starts at a time (0: one per core)")
      ->check(CLI::Range(0, 1024))
      ->needs(local);
  CLI::Option* mpi = cmd->add_flag(
      "--mpi", o->mpi, "A multistart: run as MPI ranks (mpirun -np N layerlab optimize ...): start k on rank k mod N");
  CLI::Option* slurm = cmd->add_flag(
      "--slurm", o->slurm,
      "A multistart: write a Slurm job array (DIR/slurm/array.sbatch), a gather step and submit.sh; run nothing");
  const std::vector<CLI::Option*> resources =
      AddSlurmResourceFlags(cmd, slurm, &o->slurm_resources, "the design's threads");
  CLI::Option* gather =
      cmd->add_flag("--gather", o->gather, "A multistart: only gather the report from the starts' logs");
  local->excludes(mpi)->excludes(slurm)->excludes(start)->excludes(gather);
  mpi->excludes(slurm)->excludes(start)->excludes(gather);
  slurm->excludes(start)->excludes(gather);
  start->excludes(gather);
  cmd->callback([o, resources] {
    CheckSlurmFlags(resources);
    RunOptimizeCommand(*o);
  });
}

}  // namespace layerlab::app
