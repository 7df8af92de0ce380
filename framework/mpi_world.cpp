#include "layerlab/framework/mpi_world.h"

#include <mpi.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <span>
#include <vector>

#include "layerlab/framework/error.h"
#include "layerlab/framework/thread_budget.h"

namespace layerlab {

bool MpiWorld::Launched() {
  // OpenMPI's mpirun, and the PMI of Slurm's srun and MPICH's hydra.
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_SIZE"})
    if (std::getenv(name)) return true;
  return false;
}

MpiWorld::MpiWorld() {
  int initialized = 0;
  MPI_Initialized(&initialized);
  if (!initialized) MPI_Init(nullptr, nullptr);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
}

MpiWorld::~MpiWorld() {
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (!finalized) MPI_Finalize();
}

void MpiWorld::Sum(double* values, size_t n) const {
  if (size_ == 1 || n == 0) return;
  const auto start = std::chrono::steady_clock::now();
  const double cpu_start = ProcessCpuSeconds();
  const size_t p = static_cast<size_t>(size_);
  auto begin = [&](size_t j) { return n * j / p; };
  const size_t mine = begin(rank_ + 1) - begin(rank_);
  // To rank j this rank sends only the span of chunk j that is not +0.0 (its rays reach a band of each
  // layer's rows); rank j sums the chunks, zero-filled around each span, in rank order: the same bits as
  // summing whole chunks.
  std::vector<int> spans(2 * p), spans_in(2 * p);
  for (size_t j = 0; j < p; ++j) {
    const Span span = NonzeroSpan(values, begin(j), begin(j + 1));
    spans[2 * j] = static_cast<int>(span.first), spans[2 * j + 1] = static_cast<int>(span.count);
  }
  MPI_Alltoall(spans.data(), 2, MPI_INT, spans_in.data(), 2, MPI_INT, MPI_COMM_WORLD);
  std::vector<int> send_counts(p), send_offsets(p), recv_counts(p), recv_offsets(p), chunk_counts(p), chunk_offsets(p);
  for (size_t j = 0; j < p; ++j) {
    send_counts[j] = spans[2 * j + 1];
    send_offsets[j] = static_cast<int>(begin(j)) + spans[2 * j];
    recv_counts[j] = spans_in[2 * j + 1];
    recv_offsets[j] = static_cast<int>(mine * j) + spans_in[2 * j];
    chunk_counts[j] = static_cast<int>(begin(j + 1) - begin(j));
    chunk_offsets[j] = static_cast<int>(begin(j));
    if (j != size_t(rank_))
      traffic_.sent_bytes += 8.0 * send_counts[j], traffic_.whole_chunk_bytes += 8.0 * chunk_counts[j];
  }
  std::vector<double>& chunks = chunks_;  // kept from sum to sum: a fresh block would fault its pages in
  chunks.assign(mine * p, 0.0);
  MPI_Alltoallv(values, send_counts.data(), send_offsets.data(), MPI_DOUBLE, chunks.data(), recv_counts.data(),
                recv_offsets.data(), MPI_DOUBLE, MPI_COMM_WORLD);
  std::span<double> sum(chunks.data(), mine);  // rank 0's chunk, to which the others are added
  for (size_t r = 1; r < p; ++r)
    for (size_t k = 0; k < mine; ++k) sum[k] += chunks[r * mine + k];
  MPI_Allgatherv(sum.data(), static_cast<int>(mine), MPI_DOUBLE, values, chunk_counts.data(), chunk_offsets.data(),
                 MPI_DOUBLE, MPI_COMM_WORLD);
  const double gathered = 8.0 * double(mine) * double(p - 1);
  traffic_.sent_bytes += gathered, traffic_.whole_chunk_bytes += gathered;
  ++traffic_.sums;
  traffic_.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  traffic_.cpu_seconds += ProcessCpuSeconds() - cpu_start;
}

double MpiWorld::Max(double value) const {
  double out = value;
  MPI_Allreduce(&value, &out, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  return out;
}

bool MpiWorld::Any(bool value) const {
  int in = value ? 1 : 0, out = 0;
  MPI_Allreduce(&in, &out, 1, MPI_INT, MPI_LOR, MPI_COMM_WORLD);
  return out != 0;
}

void MpiWorld::Barrier() const { MPI_Barrier(MPI_COMM_WORLD); }

void MpiWorld::ThrowIfAnyFailed(const std::string& error) const {
  int mine = error.empty() ? size_ : rank_, first = size_;
  MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
  if (first == size_) return;
  std::string what = error;
  if (first != 0) {  // the first failing rank's message, to rank 0
    int length = static_cast<int>(error.size());
    if (rank_ == first) {
      MPI_Send(&length, 1, MPI_INT, 0, 0, MPI_COMM_WORLD);
      MPI_Send(error.data(), length, MPI_CHAR, 0, 1, MPI_COMM_WORLD);
    } else if (rank_ == 0) {
      MPI_Recv(&length, 1, MPI_INT, first, 0, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
      what.assign(static_cast<size_t>(length), '\0');
      MPI_Recv(what.data(), length, MPI_CHAR, first, 1, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    }
  }
  if (rank_ != 0) throw RankStopped{};
  throw Error("rank " + std::to_string(first) + " of " + std::to_string(size_) + ": " + what);
}

void MpiWorld::Abort(const std::string& what) const {
  std::fprintf(stderr, "layerlab: error: rank %d of %d: %s\n", rank_, size_, what.c_str());
  std::fflush(stderr);
  MPI_Abort(MPI_COMM_WORLD, 1);
  std::exit(1);  // MPI_Abort does not return; for the compiler
}

}  // namespace layerlab
