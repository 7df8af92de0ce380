// The ways `layerlab sweep` runs its jobs (docs/sweeps.md): a process pool on
// this machine, MPI ranks, or a Slurm job array whose scripts it writes.
// Each returns how many jobs failed; a job already complete is skipped.
#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "layerlab/analysis/sweep_gather.h"
#include "layerlab/analysis/sweep_jobs.h"
#include "layerlab/app/process_pool.h"
#include "layerlab/framework/error.h"

namespace layerlab::app {

// One line on stdout: the job, its values, and how it ended.
void SayJob(const SweepSpec& spec, const SweepJob& job, const SweepJobState& state, const std::string& prefix = "");

// The exit status of `sweep --job ID` when another process holds that job.
inline constexpr int kJobBusyExit = 75;  // EX_TEMPFAIL: try again later

// Runs each unfinished job as `layerlab sweep SWEEP --out DIR --job ID`, at
// most `processes` at a time (posix_spawn); prints a line per job.
size_t RunSweepLocally(const SweepSpec& spec, const std::vector<SweepJob>& jobs, const std::string& out, int processes);

// DIR/slurm/array.sbatch (the array task id selects the job),
// DIR/slurm/gather.sbatch and DIR/slurm/submit.sh, as text.
struct SlurmScripts {
  std::string folder, logs, array, gather, submit;  // absolute paths
  std::string array_text, gather_text, submit_text;
};
// What the array runs: `layerlab COMMAND FILE --out DIR ARGUMENTS TASK_FLAG $SLURM_ARRAY_TASK_ID`
// per task, and the same with --gather after them all.
struct SlurmArrayCommand {
  std::string command, file, file_what;  // "sweep", the sweep file, "SWEEP (the sweep file's path)"
  std::string kind;                      // "sweep", "optimization": in comments and messages
  std::string name;                      // the job's name (checked: SlurmJobNameProblem)
  Location name_at;                      // where it comes from, and what to do about a bad one
  std::string name_note;
  int threads = 0;                     // each task's CPUs unless the resources say
  std::vector<std::string> arguments;  // more arguments for every task (quoted)
  std::string task_flag, task, tasks;  // "--job", "job of the sweep", "jobs"
  std::string gathered;                // what the gather step makes
  Location empty;                      // named when there is no task
};
SlurmArrayCommand SweepArrayCommand(const SweepSpec& spec);

// The scripts of `task_count` tasks into `out`, with `resources`. Writes
// nothing; throws layerlab::Error naming the field (the file's /name, --out,
// a resource) when a text cannot be carried safely into a script
// (app/sweep_slurm.cpp says which).
SlurmScripts MakeSlurmScripts(const SlurmArrayCommand& command, size_t task_count, const std::string& out,
                              const SlurmResources& resources);
// --slurm-time, --slurm-mem, --slurm-partition, --slurm-account and
// --slurm-cpus-per-task into `resources`, each needing `slurm`; `cpus`
// says what the CPUs default to. Returns them, for CheckSlurmFlags.
std::vector<CLI::Option*> AddSlurmResourceFlags(CLI::App* cmd, CLI::Option* slurm, SlurmResources* resources,
                                                const std::string& cpus);
// Throws layerlab::Error for a resource flag given an empty value (it would read as not given).
void CheckSlurmFlags(const std::vector<CLI::Option*>& flags);

// Writes them (and creates the logs folder); returns their paths.
std::vector<std::string> WriteSlurmScripts(const SlurmScripts& scripts);

// Under mpirun: rank 0 writes the job folders, job i runs on rank i mod N,
// rank 0 gathers. Returns the number of failed jobs on every rank; a rank that
// throws ends all ranks (MPI_Abort). Without MPI built in, refuses naming --mpi.
SweepSummary RunSweepMpi(const SweepSpec& spec, const std::vector<SweepJob>& jobs, const std::string& out,
                         bool* is_root);

}  // namespace layerlab::app
