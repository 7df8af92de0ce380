// The ways `layerlab sweep` runs its jobs (docs/sweeps.md): a process pool on
// this machine, MPI ranks, or a Slurm job array whose scripts it writes.
// Each returns how many jobs failed; a job already complete is skipped.
#pragma once

#include <string>
#include <vector>

#include "layerlab/analysis/sweep_gather.h"
#include "layerlab/analysis/sweep_jobs.h"

namespace layerlab::app {

// One line on stdout: the job, its values, and how it ended.
void SayJob(const SweepSpec& spec, const SweepJob& job, const SweepJobState& state, const std::string& prefix = "");

// The exit status of `sweep --job ID` when another process holds that job.
inline constexpr int kJobBusyExit = 75;  // EX_TEMPFAIL: try again later

// This executable, for the pool's children and the Slurm scripts.
std::string SelfExecutable();

// Runs each unfinished job as `layerlab sweep SWEEP --out DIR --job ID`, at
// most `processes` at a time (posix_spawn); prints a line per job.
size_t RunSweepLocally(const SweepSpec& spec, const std::vector<SweepJob>& jobs, const std::string& out, int processes);

// DIR/slurm/array.sbatch (the array task id selects the job),
// DIR/slurm/gather.sbatch and DIR/slurm/submit.sh, as text.
struct SlurmScripts {
  std::string folder, logs, array, gather, submit;  // absolute paths
  std::string array_text, gather_text, submit_text;
};
// The scripts of the sweep's `job_count` jobs into `out`, with `resources`.
// Writes nothing; throws layerlab::Error naming the field (the sweep file's
// /name, --out, a resource) when a text cannot be carried safely into a
// script (app/sweep_slurm.cpp says which).
SlurmScripts MakeSlurmScripts(const SweepSpec& spec, size_t job_count, const std::string& out,
                              const SlurmResources& resources);
// Writes them (and creates the logs folder); returns their paths.
std::vector<std::string> WriteSlurmScripts(const SlurmScripts& scripts);

// Under mpirun: rank 0 writes the job folders, job i runs on rank i mod N,
// rank 0 gathers. Returns the number of failed jobs on every rank; a rank that
// throws ends all ranks (MPI_Abort). Without MPI built in, refuses naming --mpi.
SweepSummary RunSweepMpi(const SweepSpec& spec, const std::vector<SweepJob>& jobs, const std::string& out,
                         bool* is_root);

}  // namespace layerlab::app
