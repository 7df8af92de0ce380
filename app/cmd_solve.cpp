// layerlab solve SCENE.json --target LF_DIR --solver NAME --out DIR: factorize
// a target light field (or a target scene, rendered first) into panel images,
// with progress on the terminal. Under mpirun the rays are partitioned
// across the ranks in tiles of view rows by pixel rows (docs/mpi.md): each rank
// reads (or renders) only its tile, the solvers sum over the ranks
// (framework/mpi_ranks.h), and rank 0 alone reports and writes.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <iostream>
#include <iterator>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include "layerlab/analysis/frame_sequence.h"
#include "layerlab/analysis/report_parts.h"
#include "layerlab/analysis/solve_job.h"
#include "layerlab/analysis/target_source.h"
#include "layerlab/app/command_line.h"
#include "layerlab/app/command_result.h"
#include "layerlab/app/commands.h"
#include "layerlab/app/number_list.h"
#include "layerlab/app/optics_options.h"
#include "layerlab/app/pose_option.h"
#include "layerlab/app/solver_flags.h"
#include "layerlab/app/target_option.h"
#include "layerlab/framework/atomic_file.h"
#include "layerlab/framework/interrupt.h"
#include "layerlab/framework/lightfield_io.h"
#include "layerlab/framework/mpi_ranks.h"
#include "layerlab/framework/thread_budget.h"
#include "layerlab/solvers/solution_writer.h"
#if LAYERLAB_WITH_MPI
#include "layerlab/framework/mpi_world.h"
#endif
#include "layerlab/framework/progress.h"
#include "layerlab/framework/staged_output.h"
#include "layerlab/framework/warnings.h"
#include "layerlab/solvers/memory_estimate.h"
#include "layerlab/solvers/solve_config.h"
#include "layerlab/solvers/solver_checkpoint.h"
#include "layerlab/systems/compile.h"

namespace layerlab::app {
namespace {

struct Options {
  std::string scene, out;
  TargetOption target;
  SolverFlags solver;
  bool write_lightfield = false, resume = false;
  int checkpoint_every = 0;
  std::string max_memory;
  PoseOption pose;
  OpticsOptions optics;  // --fill-factor
  std::string start_from;
  FrameSequenceOptions frames;  // --frames: a moving target, frame by frame
};

// The ranks of this solve: rank 0 of 1 unless mpirun started it.
struct Ranks {
#if LAYERLAB_WITH_MPI
  std::unique_ptr<MpiWorld> world;
#endif
  int rank = 0, size = 1;
  mutable bool agreed = false;  // a failure ThrowIfAnyFailed reported: every rank knows
  bool root() const { return rank == 0; }
  // Collective under MPI: any rank's failure (`error` non-empty) ends every rank, rank 0 naming it.
  void ThrowIfAnyFailed(const std::string& error) const {
#if LAYERLAB_WITH_MPI
    if (world) {
      try {
        world->ThrowIfAnyFailed(error);
      } catch (const Error&) {
        agreed = true;
        throw;
      }
      return;
    }
#endif
    if (!error.empty()) throw Error(error);
  }
  const RankGroup* group() const {
#if LAYERLAB_WITH_MPI
    return world.get();
#else
    return nullptr;
#endif
  }
};

// This rank's rays of the target: its tile read from the folder, or rendered
// from the target scene; the whole target for one process.
std::unique_ptr<Target> LoadRankTarget(const SolveConfig& config, const Ranks& ranks, const LightFieldGeometry& tile) {
  if (!ranks.group()) return LoadOrRenderTarget(config, "target");
  auto target = std::make_unique<Target>();
  if (!config.target.empty()) {
    target->source = config.target;
    if (ranks.root()) Note("target: loading the light field " + config.target + ", a tile per rank");
    target->light_field = ReadLightField(config.target, {.load_depth = false,
                                                         .first_view_row = tile.first_view_row,
                                                         .view_rows = tile.views_y,
                                                         .first_pixel_row = tile.first_pixel_row,
                                                         .pixel_rows = tile.rows});
    return target;
  }
#if LAYERLAB_WITH_EMBREE
  if (!config.target_scene.empty()) {
    target->source = config.target_scene;
    target->rendered = true;
    target->scene = std::make_unique<TargetScene>(LoadTarget(config.target_scene));
    MoveTargetScene(target->scene.get(), config.target_moved_m);  // a binocular eye's own display: from its axis
    target->scene->geometry = tile;
    if (ranks.root()) Note("target: rendering " + config.target_scene + ", a tile per rank");
    target->light_field = RenderTarget(*target->scene);
    return target;
  }
#endif
  return LoadOrRenderTarget(config, "target");  // says why there is none
}

// The overrides step: the command line's values over the scene's "solve"
// section; any value given is checked by SolverOptions.
void ApplyOverrides(const Options& o, SolveConfig* config) {
  ApplySolverFlags(o.solver, *config);  // any value given is checked by SolverOptions
  if (const std::string why = ObjectiveRefusal(config->solver, config->options.objective); !why.empty())
    throw Error("--objective " + ToString(config->options.objective) + ": " + why);
}

// What cannot be split across MPI ranks, refused before anything is read.
void RefuseWithRanks(const Options& o, const SolverOptions& opt, const Ranks& ranks) {
  if (ranks.size <= 1) return;
  // The retinal operator blends views across the whole eyebox, so it needs every view on one rank.
  if (opt.objective == ObjectiveKind::kRetinal || opt.measure_focal_stack)
    throw Error("the retinal objective and --measure-focal-stack: not with MPI ranks (" + std::to_string(ranks.size) +
                "); run the solve in one process");
  if (o.checkpoint_every > 0 || o.resume)
    throw Error("--checkpoint-every and --resume: not with MPI ranks (" + std::to_string(ranks.size) +
                "); run the solve in one process to checkpoint it");
}

// The rays of the target this process solves: its rank's tile, or all of them.
struct RankViews {
  LightFieldGeometry whole, block;
  RayTile tile;
};

RankViews ViewsOfRank(const SolveConfig& config, const Ranks& ranks) {
  RankViews v;
  v.whole = TargetGeometry(config);
  v.tile = RayTileOfRank(v.whole.views_y, v.whole.rows, ranks.rank, ranks.size);
  v.block = ranks.group() ? v.whole.ViewRows(v.tile.first_view_row, v.tile.view_rows)
                                .PixelRows(v.tile.first_pixel_row, v.tile.pixel_rows)
                          : v.whole;
  return v;
}

// "view rows 0-12 x pixel rows 0-99 of 13 x 200" for the notes.
std::string TileName(const RankViews& v) {
  auto span = [](int first, int count) { return std::to_string(first) + "-" + std::to_string(first + count - 1); };
  return "view rows " + span(v.tile.first_view_row, v.tile.view_rows) + " x pixel rows " +
         span(v.tile.first_pixel_row, v.tile.pixel_rows) + " of " + std::to_string(v.whole.views_y) + " x " +
         std::to_string(v.whole.rows) + " (" + std::to_string(v.tile.view_blocks) + " x " +
         std::to_string(v.tile.pixel_blocks) + " tiles)";
}

#if LAYERLAB_WITH_MPI
// A partitioned solve's per-iteration figures are counted from the end of this iteration to the last
// (the first iterations also fault in the buffers, a cost that varies from run to run).
constexpr int kTrafficFromIteration = 2;

// This rank's CPU seconds and its sums' traffic at the end of iteration kTrafficFromIteration.
struct TrafficMark {
  bool set = false;
  double cpu_seconds = 0;
  MpiWorld::Traffic traffic;
};

// Collective: what the ranks' sums sent, on average per rank and iteration, and the CPU seconds of each
// rank's compute and of its sums per iteration, from `mark` to the last iteration, said by rank 0.
void NoteTraffic(const MpiWorld& world, const RankViews& views, int iterations, const TrafficMark& mark) {
  const MpiWorld::Traffic& end = world.traffic();
  const MpiWorld::Traffic& from = mark.traffic;
  const double cpu = mark.set ? ProcessCpuSeconds() - mark.cpu_seconds : 0;
  const double sums_cpu = end.cpu_seconds - from.cpu_seconds, compute = cpu - sums_cpu;
  double totals[] = {end.sent_bytes - from.sent_bytes,
                     end.whole_chunk_bytes - from.whole_chunk_bytes,
                     double(end.sums - from.sums),
                     compute,
                     sums_cpu,
                     end.seconds - from.seconds};
  const int counted = iterations - kTrafficFromIteration;
  if (!world.Any(!mark.set || counted < 1)) {
    world.Sum(totals, std::size(totals));
    const double most_compute = world.Max(compute), p = world.size(), per_rank = 1.0 / (p * counted);
    char line[400];
    std::snprintf(line, sizeof line,
                  "MPI: %d ranks in %d x %d tiles, per rank and iteration (iterations %d-%d): sent %.3f MB in %.1f "
                  "sums (%.0f %% of whole chunks' %.3f MB); CPU %.4f s computing (the most %.4f s), %.4f s in the "
                  "sums (%.4f s wall)",
                  world.size(), views.tile.view_blocks, views.tile.pixel_blocks, kTrafficFromIteration + 1, iterations,
                  totals[0] * per_rank * 1e-6, totals[2] * per_rank,
                  totals[1] > 0 ? 100 * totals[0] / totals[1] : 100.0, totals[1] * per_rank * 1e-6,
                  totals[3] * per_rank, most_compute / counted, totals[4] * per_rank, totals[5] * per_rank);
    Note(line);
  }
}
#endif

// The memory check: refuses what cannot fit before reading the views or
// rendering the target (per rank: its block's rays).
void CheckMemory(const Options& o, const DisplaySystem& system, const SolveConfig& config, const RankViews& views,
                 const Ranks& ranks) {
  const size_t limit = o.max_memory.empty() ? 0 : ParseByteSize(o.max_memory, "--max-memory");
  const std::string limit_name = "--max-memory " + FormatBytes(double(limit));
  std::string refused;
  size_t need = 0;
  try {
    need = RefuseSolveBeyondMemory(system, views.block, config, config.options.threads, limit,
                                   ranks.size > 1 ? limit_name + " per rank" : limit_name);
  } catch (const Error& e) {
    refused = e.what();
  }
  ranks.ThrowIfAnyFailed(refused);
  if (ranks.size > 1)
    Note("rank 0 of " + std::to_string(ranks.size) + " needs about " + FormatBytes(double(need)) + " for " +
         TileName(views) + " (each rank its own tile's share)");
  else
    Note("the solve needs about " + FormatBytes(double(need)));
}

// The staging step: the results are built beside the earlier ones and
// switched into place when complete; by rank 0 alone.
void Stage(const Options& o, const SolveConfig& config, const Ranks& ranks, std::optional<StagedOutput>* stage) {
  if (!ranks.root()) return;
  stage->emplace(o.out, "solve",
                 std::vector<std::string>{"patterns", "panels", "lightfield", "trace.csv", "report.txt", "report.json",
                                          "checkpoint", "index.html", "pattern_previews", "panel_previews",
                                          "psnr_vs_time.svg", "frames.csv", "frames.txt"},
                 std::vector<NamedInput>{{o.scene, "the scene"},
                                         {config.target, "the target"},
                                         {config.target_scene, "the target scene"},
                                         {o.start_from, "the solve started from"}});
  for (const std::string& line : (*stage)->recovered()) Note("solve: " + line);
}

// This rank's views of the target; a rank that cannot read its own ends every rank.
std::unique_ptr<Target> LoadTargetOfRank(const SolveConfig& config, const Ranks& ranks, const RankViews& views) {
  std::unique_ptr<Target> target;
  std::string unread;
  try {
    target = LoadRankTarget(config, ranks, views.block);
  } catch (const Error& e) {
    unread = e.what();
  }
  ranks.ThrowIfAnyFailed(unread);
  return target;
}

// Checkpoints written every N iterations, and a solve resumed from one: the
// hook the solve job calls with the model before the solver starts.
struct Checkpointing {
  const Options& o;
  const SolveConfig& config;
  const LightField& views;
  CheckpointInputs digest;
  std::optional<SolverCheckpoint> resume;
  std::optional<Patterns> warm;

  void operator()(const DisplayModel& model, SolverOptions* opt) {
    InstallInterruptHandler();
    opt->interrupted = Interrupted;
    const std::string folder = (std::filesystem::path(o.out) / "checkpoint").string();
    if (o.checkpoint_every < 0) throw Error("--checkpoint-every: must be 0 (none) or positive");
    opt->checkpoint_every = o.checkpoint_every;
    // Hashing the target costs a pass over it: only when a checkpoint is written or read.
    if (o.checkpoint_every > 0 || o.resume)
      digest = CheckpointDigest(model, config.sampling, views, config.solver, *opt);
    if (o.checkpoint_every > 0)
      opt->checkpoint = [this, &model, folder](const SolverCheckpoint& c) {
        WriteCheckpoint(model, c, folder, digest);
      };
    if (!o.start_from.empty()) {
      if (o.resume) throw Error("--start-from: not with --resume (a checkpoint holds its own patterns)");
      warm = ReadPatterns(model, o.start_from);
      opt->initial_patterns = &*warm;
    }
    if (!o.resume) return;
    RefuseMismatchedCheckpoint(folder, digest);
    resume = ReadCheckpoint(model, folder);
    opt->resume = &*resume;
    Note("resuming " + resume->solver + " from iteration " + std::to_string(resume->iteration));
  }
};

// The writing and page steps, by rank 0: the solution, the page, the switch into place.
void WriteResults(const Options& o, const Scene& scene, const DisplaySystem& system, const SolveConfig& config,
                  const DisplayModel& written, const SolvedJob& solved, StagedOutput& stage) {
  try {
    RunReportPage page =
        CommandPage("solve", o.scene, scene.name.empty() ? std::filesystem::path(o.scene).stem().string() : scene.name,
                    scene.description, CommandLine());
    page.system = &system;
    page.steps = {{"solve (" + config.solver + ", " + std::to_string(solved.report.iterations) + " iterations)",
                   solved.report.seconds}};
    page.warnings = solved.report.warnings;
    WriteSolveJob(written, system, solved, stage.staging(), "", o.write_lightfield, &page);
    WriteReportPage(page, stage.staging());
  } catch (const Error& e) {
    throw stage.Explain(e);
  }
  const StagedOutput::Switched switched = stage.Commit();
  if (!switched.removed.empty())
    std::fprintf(stderr, "solve: removed %zu file%s an earlier solve wrote into %s\n", switched.removed.size(),
                 switched.removed.size() == 1 ? "" : "s", o.out.c_str());
  CommandResult result("solve");
  result.Text(solved.report.BriefReport() + "\nwrote " + o.out + "/{index.html,patterns,panels,trace.csv,report.txt," +
              "report.json" + (o.write_lightfield ? ",lightfield" : "") + "}\n");
  result["out"] = o.out;
  result["report"] = ReportSummaryJson(solved.report);
  result.Print();
}

// --frames: a moving target solved frame by frame (analysis/frame_sequence.h). The last frame's solution is
// written as a solve's, with frames.csv and frames.txt beside it.
void SolveFrames(const Options& o, const Scene& scene, const DisplaySystem& system, const SolveJob& job,
                 const Ranks& ranks) {
  if (o.frames.frames < 1) throw Error("--frames: must be at least 1, got " + std::to_string(o.frames.frames));
  if (ranks.size > 1) throw Error("--frames: not with MPI ranks; run it in one process");
  if (o.resume || o.checkpoint_every > 0 || !o.start_from.empty())
    throw Error("--frames: not with --resume, --checkpoint-every or --start-from (each frame starts from the last)");
  const SolveConfig& config = job.config;
  if (config.target_scene.empty())
    throw Error(
        "--frames: needs a target scene that moves (--target-scene, or the scene's solve.target_scene); "
        "a light-field folder holds one frame");
  TargetScene moving = LoadTarget(config.target_scene);
  MoveTargetScene(&moving, config.target_moved_m);
  RequireFrameSequence(job, moving, o.frames);
  CheckMemory(o, system, config, ViewsOfRank(config, ranks), ranks);
  std::optional<StagedOutput> stage;
  Stage(o, config, ranks, &stage);
  Progress progress("frames", size_t(o.frames.frames));
  const FrameSequence sequence = SolveFrameSequence(job, moving, o.frames, [&](const FrameRow& r) {
    char detail[160];
    std::snprintf(detail, sizeof detail, "frames  last: %d iterations %.3f s  PSNR %.2f dB", r.iterations,
                  r.solve_seconds, r.psnr_db);
    progress.Update(size_t(r.frame + 1), detail);
  });
  progress.Finish("");
  const std::string summary = FramesSummary(sequence, o.frames, moving);
  try {
    WriteFramesCsv(sequence, stage->staging() + "/frames.csv");
    WriteFileAtomically(stage->staging() + "/frames.txt", summary);
  } catch (const Error& e) {
    throw stage->Explain(e);
  }
  Note(summary);
  WriteResults(o, scene, system, config, *sequence.last.model, sequence.last, *stage);
}

// The solve of one process, or of this rank: the solve job's steps
// (analysis/solve_job.h) with the command line's values.
void Solve(const Options& o, Ranks& ranks) {
  const Scene scene = LoadScene(o.scene);
  DisplaySystem system = Compile(scene);
  if (const std::string warning = ApplyPoseOption(o.pose, &system); !warning.empty())
    system.warnings.push_back(warning);
  ApplyOpticsOptions(o.optics, &system);
  SolveJob job;
  job.system = &system;
  job.config = SolveJobConfig(scene, system, o.solver.solver);
  SolveConfig& config = job.config;
  ApplyTargetOption(o.target, config);
  RequireTarget(config, o.scene);
  ApplyOverrides(o, &config);
  if ((!o.pose.pupil_offset.empty() || !o.pose.gaze.empty()) && config.options.objective != ObjectiveKind::kRetinal)
    throw Error(std::string(o.pose.gaze.empty() ? "--pupil-offset" : "--gaze") +
                ": the light-field objective weighs every view of the eyebox alike; a solve for where the eye is "
                "needs --objective retinal (with joint or quasi-newton)");
  if (const std::string beyond = EyeboxGridWarning(EyeboxPupils(config.options), system.eye); !beyond.empty())
    system.warnings.push_back(beyond);
  if (o.frames.frames != 0) return SolveFrames(o, scene, system, job, ranks);
  RefuseWithRanks(o, config.options, ranks);
  const RankViews views = ViewsOfRank(config, ranks);
  CheckMemory(o, system, config, views, ranks);
  std::optional<StagedOutput> stage;
  Stage(o, config, ranks, &stage);
  std::unique_ptr<Target> target = LoadTargetOfRank(config, ranks, views);
  Checkpointing checkpointing{o, config, target->light_field, {}, {}, {}};
  job.progress_label = config.solver;
  job.ranks = ranks.group();
  job.before_solve = std::ref(checkpointing);
#if LAYERLAB_WITH_MPI
  TrafficMark mark;
  if (ranks.world)
    job.before_solve = [&](const DisplayModel& model, SolverOptions* opt) {
      checkpointing(model, opt);
      opt->progress = [&](const IterationRecord& row) {
        if (row.iteration == kTrafficFromIteration) mark = {true, ProcessCpuSeconds(), ranks.world->traffic()};
      };
    };
#endif
  SolvedJob solved = RunSolveJob(job, target->light_field, target.get());
  SolverReport& report = solved.report;
#if LAYERLAB_WITH_MPI
  if (ranks.world) NoteTraffic(*ranks.world, views, report.iterations, mark);
  if (!ranks.root()) {  // every rank holds the same patterns and report: rank 0 writes them
    target.reset();
    ranks.world->Barrier();  // rank 0 has written (or ended every rank)
    return;
  }
  // The solution is written for the whole light field.
  std::optional<DisplayModel> whole_model;
  if (ranks.group()) whole_model.emplace(system, views.whole, config.sampling);
  if (whole_model) target.reset();
  const DisplayModel& written = whole_model ? *whole_model : *solved.model;
#else
  const DisplayModel& written = *solved.model;
#endif
  std::vector<std::string> found = system.warnings;  // the compile's and the target's first
  for (const std::string& w : TargetGeometryWarnings(system, views.whole)) found.push_back(w);
  report.warnings.insert(report.warnings.begin(), found.begin(), found.end());
  SayWarnings(report.warnings);
  if (!report.IsSolutionUsable())
    throw Error("the solve failed: " + report.message + " (" + report.BriefReport() + "); nothing was written");
  WriteResults(o, scene, system, config, written, solved, *stage);
#if LAYERLAB_WITH_MPI
  if (ranks.world) ranks.world->Barrier();  // the others wait for the results to be in place
#endif
  if (report.termination == Termination::kInterrupted)
    throw InterruptedError("interrupted: " + o.out + " holds the patterns of iteration " +
                           std::to_string(report.iterations) + ", the last complete one");
}

}  // namespace

void AddSolveCommand(CLI::App& app) {
  auto o = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand("solve", "Factorize a target light field into layer patterns");
  cmd->add_option("scene", o->scene, "Scene file (JSON); its \"solve\" section gives the defaults")->required();
  AddTargetOptions(cmd, o->target, " (default: the scene's solve section)");
  cmd->add_option("--out", o->out, "Output folder")->required();
  AddSolverFlags(cmd, o->solver);
  cmd->add_flag("--write-lightfield", o->write_lightfield, "Also write the synthesized light field");
  cmd->add_option("--checkpoint-every", o->checkpoint_every,
                  "Write OUT/checkpoint every N iterations (and when stopped early)");
  cmd->add_flag("--resume", o->resume, "Continue from OUT/checkpoint (same scene, target and solver)");
  AddPoseOptions(cmd, o->pose);
  AddPanelOptions(cmd, o->optics);
  cmd->add_option("--start-from", o->start_from,
                  "Begin from the patterns of an earlier solve (its output folder), e.g. for the eye's last position");
  cmd->add_option("--frames", o->frames.frames,
                  "Solve N frames of a moving target scene, each from the frame before (docs/target-format.md)");
  cmd->add_option("--frame-iterations", o->frames.frame_iterations,
                  "With --frames: iterations of each frame after the first (default 3)");
  cmd->add_option("--cold-every", o->frames.cold_every,
                  "With --frames: also solve every K-th frame cold, as its PSNR reference (default 1; 0: none)");
  cmd->add_option("--max-memory", o->max_memory,
                  "Refuse a run estimated to need more (e.g. 2 GB; default: the machine's memory)");
  cmd->callback([o, cmd] {
    for (const char* flag : {"--frame-iterations", "--cold-every"})
      if (cmd->count(flag) && o->frames.frames == 0) throw Error(std::string(flag) + ": only with --frames N");
    Ranks ranks;
#if LAYERLAB_WITH_MPI
    if (MpiWorld::Launched()) {
      ranks.world = std::make_unique<MpiWorld>();
      ranks.rank = ranks.world->rank(), ranks.size = ranks.world->size();
      if (!ranks.root()) SetVerbosity(Verbosity::kQuiet);  // rank 0 speaks for all
    }
    try {
      Solve(*o, ranks);
    } catch (const RankStopped&) {
      ranks.world.reset();  // rank 0 said why
      std::exit(1);
    } catch (const Error& e) {
      // Ranks 0 reports a failure every rank knows of; any other ends every rank, naming its own.
      if (!ranks.world || ranks.size == 1 || ranks.agreed) throw;
      ranks.world->Abort(e.what());
    }
#else
    Solve(*o, ranks);
#endif
  });
}

}  // namespace layerlab::app
