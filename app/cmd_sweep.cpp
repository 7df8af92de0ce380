// layerlab sweep SWEEP.json --out DIR: a design study over a grid of scene
// parameters (analysis/sweep_spec.h, docs/sweeps.md). Expands the grid into
// job folders, runs the jobs (--local -j N, --mpi under mpirun, or --slurm to
// write a job array), and gathers one table and plots. Exits non-zero when a
// job failed; the others still run, and a run again skips what is complete.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <optional>
#include <string>
#include <thread>

#include "layerlab/analysis/sweep_gather.h"
#include "layerlab/app/command_result.h"
#include "layerlab/app/commands.h"
#include "layerlab/app/sweep_runners.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/progress.h"
#if LAYERLAB_WITH_MPI
#include "layerlab/framework/mpi_world.h"
#endif

namespace layerlab::app {

void SayJob(const SweepSpec& spec, const SweepJob& job, const SweepJobState& s, const std::string& prefix) {
  std::string values;
  for (size_t k = 0; k < spec.parameters.size(); ++k)
    values += (k ? ", " : "") + spec.parameters[k].name + " " + spec.parameters[k].labels[job.choice[k]];
  // Progress, on stderr as every command's: the result on stdout is the summary (GatherAndReport).
  if (s.complete)
    std::fprintf(stderr, "%ssweep: job %s (%s) complete in %.1f s\n", prefix.c_str(), job.id.c_str(), values.c_str(),
                 s.seconds);
  else if (s.busy)
    std::fprintf(stderr, "%ssweep: job %s (%s) not run: %s\n", prefix.c_str(), job.id.c_str(), values.c_str(),
                 s.error.c_str());
  else
    std::fprintf(stderr, "%ssweep: job %s (%s) failed: %s\n", prefix.c_str(), job.id.c_str(), values.c_str(),
                 s.error.empty() ? "the job process ended without a record" : s.error.c_str());
}

namespace {

struct SweepOptions {
  std::string sweep, out, job;
  bool local = false, mpi = false, slurm = false, gather = false;
  int processes = 1;
  SlurmResources slurm_resources;  // --slurm-time ...: over the sweep file's "slurm"
};

void CheckSlurmOptions(const SlurmResources& r) {
  for (const auto& [key, value] : {std::pair{"time", &r.time}, std::pair{"mem", &r.mem},
                                   std::pair{"partition", &r.partition}, std::pair{"account", &r.account}})
    if (!value->empty())
      if (const std::string problem = SlurmValueProblem(key, *value); !problem.empty())
        throw Error(std::string("--slurm-") + key + ": " + problem);
}

// The summary every runner prints (local, MPI, --gather), and the exit: non-zero when a job failed or did
// not run.
void ReportSweep(const std::vector<SweepJob>& jobs, const SweepSummary& s, const std::string& out) {
  CommandResult result("sweep");
  result.Text("sweep: " + std::to_string(jobs.size()) + " jobs: " + std::to_string(s.complete) + " complete, " +
              std::to_string(s.failed) + " failed, " + std::to_string(s.pending) + " not run; table " + out +
              "/table.html\n");
  result["out"] = out;
  result["jobs"] = jobs.size();
  result["complete"] = s.complete;
  result["failed"] = s.failed;
  result["not_run"] = s.pending;
  result["table"] = out + "/table.csv";
  result.Print();
  if (s.failed || s.pending) throw CLI::RuntimeError(1);
}

// The table gathered from the job records, and the summary.
void GatherAndReport(const SweepSpec& spec, const std::vector<SweepJob>& jobs, const std::string& out) {
  ReportSweep(jobs, GatherSweep(spec, jobs, out), out);
}

void RunSweepCommand(const SweepOptions& o) {
  CheckSlurmOptions(o.slurm_resources);
#if LAYERLAB_WITH_MPI
  // Without a launcher MPI_Init would start a singleton, or fail with a page of Open MPI's text.
  if (o.mpi && !MpiWorld::Launched())
    throw Error("--mpi: this process was not started by an MPI launcher; run it as `mpirun -np N layerlab sweep " +
                o.sweep + " --out " + o.out +
                " --mpi` (or under srun), or leave out --mpi to run the jobs here (--local -j N)");
#endif
  const SweepSpec spec = ReadSweepSpec(o.sweep);
  const std::vector<SweepJob> jobs = ExpandSweep(spec, o.out);
  if (!o.job.empty()) {  // one job: what a pool process and a Slurm task run
    const char* task = std::getenv("SLURM_ARRAY_TASK_ID");
    const SweepJob& job = FindSweepJob(jobs, o.job);
    bool ran = false;
    const SweepJobState s = RunSweepJob(spec, job, o.out, task ? "slurm task " + std::string(task) : "local", &ran);
    if (CurrentVerbosity() != Verbosity::kQuiet) SayJob(spec, job, s, ran || s.busy ? "" : "(already complete) ");
    if (s.busy) throw CLI::RuntimeError(kJobBusyExit);
    if (s.failed) throw CLI::RuntimeError(1);
    return;
  }
  if (o.gather) return GatherAndReport(spec, jobs, o.out);
  if (o.mpi) {
#if LAYERLAB_WITH_MPI
    bool root = false;
    const SweepSummary summary = RunSweepMpi(spec, jobs, o.out, &root);
    if (root) ReportSweep(jobs, summary, o.out);
    if (summary.failed) throw CLI::RuntimeError(1);
    return;
#else
    throw Error(
        "--mpi: this layerlab was built without MPI (configure with -DLAYERLAB_WITH_MPI=ON; it needs "
        "OpenMPI: apt-get install libopenmpi-dev openmpi-bin)");
#endif
  }
  std::optional<SlurmScripts> scripts;  // made, and so checked, before anything is written
  if (o.slurm) {
    SlurmResources resources = spec.slurm;
    resources.Override(o.slurm_resources);
    scripts = MakeSlurmScripts(SweepArrayCommand(spec), jobs.size(), o.out, resources);
  }
  const FileLock lock = LockSweepFolder(spec, o.out);
  const size_t written = WriteSweepFolders(spec, jobs, o.out);
  Note("sweep: " + std::to_string(jobs.size()) + " jobs in " + o.out + "/jobs (" + std::to_string(written) +
       " scenes written)");
  if (scripts) {
    CommandResult result("sweep");
    result["out"] = o.out;
    result["jobs"] = jobs.size();
    const std::vector<std::string> written_scripts = WriteSlurmScripts(*scripts);
    for (const std::string& script : written_scripts) result.Text("sweep: wrote " + script + "\n");
    result["slurm_scripts"] = written_scripts;
    result.Text("sweep: submit with sh " + o.out + "/slurm/submit.sh\n");
    result["submit"] = "sh " + o.out + "/slurm/submit.sh";
    result.Print();
    return;
  }
  RunSweepLocally(spec, jobs, o.out,
                  o.processes > 0 ? o.processes : std::max(1, static_cast<int>(std::thread::hardware_concurrency())));
  GatherAndReport(spec, jobs, o.out);
}

}  // namespace

void AddSweepCommand(CLI::App& app) {
  auto o = std::make_shared<SweepOptions>();
  CLI::App* cmd = app.add_subcommand(
      "sweep",
      "A design study: a base scene's parameters over a grid of values, one job per point (solve, retina, "
      "contrast), gathered into one table and plots (docs/sweeps.md)");
  cmd->add_option("sweep", o->sweep, "Sweep file (JSON, layerlab-sweep/1)")->required();
  cmd->add_option("--out", o->out, "Output folder: manifest.json, jobs/, table.csv, table.html, plots/")->required();
  CLI::Option* local = cmd->add_flag("--local", o->local, "Run the jobs on this machine, a process pool (the default)");
  cmd->add_option("-j,--jobs", o->processes, "With --local: jobs at a time (0: one per core; default 1)")
      ->check(CLI::Range(0, 1024));
  CLI::Option* mpi =
      cmd->add_flag("--mpi", o->mpi, "Run as MPI ranks (mpirun -np N layerlab sweep ...): job i on rank i mod N");
  CLI::Option* slurm =
      cmd->add_flag("--slurm", o->slurm,
                    "Write a Slurm job array (DIR/slurm/array.sbatch), a gather step and submit.sh; run nothing");
  const std::vector<CLI::Option*> resources =
      AddSlurmResourceFlags(cmd, slurm, &o->slurm_resources, "the sweep's threads");
  CLI::Option* job = cmd->add_option("--job", o->job, "Run only this job (its index), e.g. from a Slurm array task");
  CLI::Option* gather = cmd->add_flag("--gather", o->gather, "Only gather the table and plots from the job records");
  local->excludes(mpi)->excludes(slurm)->excludes(job)->excludes(gather);
  mpi->excludes(slurm)->excludes(job)->excludes(gather);
  slurm->excludes(job)->excludes(gather);
  job->excludes(gather);
  cmd->callback([o, resources] {
    CheckSlurmFlags(resources);
    RunSweepCommand(*o);
  });
}

}  // namespace layerlab::app
