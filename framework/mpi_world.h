// MPI_COMM_WORLD as the ranks of a partitioned solve (framework/mpi_ranks.h).
// Built only with LAYERLAB_WITH_MPI; the process is an MPI rank when mpirun
// (or another MPI launcher) started it, otherwise it runs as one process.
#pragma once

#include <string>
#include <vector>

#include "layerlab/framework/mpi_ranks.h"

namespace layerlab {

// Thrown on a rank other than 0 when another rank failed (rank 0 says why).
struct RankStopped {};

class MpiWorld final : public RankGroup {
 public:
  // Whether an MPI launcher started this process (its environment says so).
  static bool Launched();
  MpiWorld();            // MPI_Init unless done
  ~MpiWorld() override;  // MPI_Finalize
  int rank() const override { return rank_; }
  int size() const override { return size_; }
  // A reduce-scatter and an allgather: rank j adds chunk j of every rank's
  // values in rank order, then every rank gathers the chunks. Of a chunk a
  // rank sends only its NonzeroSpan. For one rank the values are left as they are.
  void Sum(double* values, size_t n) const override;
  // What this rank's Sum calls have sent (bytes, and the bytes the same sums
  // would have sent as whole chunks) and the seconds they took (wall, CPU).
  struct Traffic {
    size_t sums = 0;
    double sent_bytes = 0, whole_chunk_bytes = 0;
    double seconds = 0, cpu_seconds = 0;
  };
  const Traffic& traffic() const { return traffic_; }
  double Max(double value) const override;
  bool Any(bool value) const override;
  void Barrier() const;
  // Collective: every rank says whether it failed (`error` non-empty). When
  // any did, rank 0 throws layerlab::Error "rank R of N: error" for the first
  // that failed and the other ranks throw RankStopped, so that every rank
  // ends with its destructors run (an output being staged is removed).
  void ThrowIfAnyFailed(const std::string& error) const;
  // "layerlab: error: rank R of N: what" on stderr, then every rank ends (exit 1).
  [[noreturn]] void Abort(const std::string& what) const;

 private:
  int rank_ = 0, size_ = 1;
  mutable Traffic traffic_;
  mutable std::vector<double> chunks_;
};

}  // namespace layerlab
