// `mpirun -np N layerlab sweep SWEEP.json --out DIR --mpi`: the jobs dealt to
// the ranks, job i to rank i mod N (the same split on every run, so a resumed
// sweep gives each rank the same jobs). Each rank runs its jobs in turn in its
// own process; only rank 0 writes the job folders' manifest and the table.
#include <mpi.h>

#include <cstdio>
#include <exception>
#include <optional>

#include "layerlab/analysis/sweep_gather.h"
#include "layerlab/app/sweep_runners.h"
#include "layerlab/framework/error.h"

namespace layerlab::app {

SweepSummary RunSweepMpi(const SweepSpec& spec, const std::vector<SweepJob>& jobs, const std::string& out,
                         bool* is_root) {
  int initialized = 0;
  MPI_Initialized(&initialized);
  if (!initialized) MPI_Init(nullptr, nullptr);
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  *is_root = rank == 0;
  // A rank that cannot go on ends every rank: the others would wait at the next collective for ever.
  auto abort_all = [&](const std::string& what) {
    std::fprintf(stderr, "layerlab: error: rank %d of %d: %s\n", rank, size, what.c_str());
    std::fflush(stderr);
    MPI_Abort(MPI_COMM_WORLD, 1);
  };
  std::optional<FileLock> lock;  // rank 0's, held to the end
  try {
    if (rank == 0) lock.emplace(LockSweepFolder(spec, out));
    if (rank == 0) WriteSweepFolders(spec, jobs, out);
  } catch (const std::exception& e) {
    abort_all(e.what());
  }
  MPI_Barrier(MPI_COMM_WORLD);
  unsigned long failed = 0, ran = 0;
  try {
    const std::string runner = "mpi rank " + std::to_string(rank) + " of " + std::to_string(size);
    for (size_t i = static_cast<size_t>(rank); i < jobs.size(); i += static_cast<size_t>(size)) {
      bool did = false;
      const SweepJobState s = RunSweepJob(spec, jobs[i], out, runner, &did);
      if (s.failed) ++failed;
      ran += did;
      SayJob(spec, jobs[i], s, "rank " + std::to_string(rank) + ": ");
    }
  } catch (const std::exception& e) {
    abort_all(e.what());
  }
  unsigned long total_failed = 0, total_ran = 0;
  MPI_Allreduce(&failed, &total_failed, 1, MPI_UNSIGNED_LONG, MPI_SUM, MPI_COMM_WORLD);
  MPI_Allreduce(&ran, &total_ran, 1, MPI_UNSIGNED_LONG, MPI_SUM, MPI_COMM_WORLD);
  SweepSummary summary;  // rank 0's from the table; the others know the failures
  summary.failed = total_failed;
  if (rank == 0) {
    std::fprintf(stderr, "sweep: %lu jobs ran on %d ranks, %lu skipped as complete\n", total_ran, size,
                 static_cast<unsigned long>(jobs.size()) - total_ran);
    try {
      summary = GatherSweep(spec, jobs, out);
    } catch (const std::exception& e) {
      abort_all(e.what());
    }
  }
  MPI_Barrier(MPI_COMM_WORLD);  // the table is in place before any rank reports success
  MPI_Finalize();
  return summary;
}

}  // namespace layerlab::app
