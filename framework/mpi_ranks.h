// The ranks of a view-partitioned solve (`mpirun -np N layerlab solve`,
// docs/mpi.md): each rank holds a block of whole view rows, and every sum over
// rays a solver makes (update numerators and denominators, gradients, the
// objective) is summed across the ranks here, at the point where the solver
// has merged its threads' sums. With no ranks installed (one process, or a
// build without MPI) every call leaves its values as they are.
#pragma once

#include <cstddef>
#include <initializer_list>
#include <span>
#include <vector>

namespace layerlab {

class RankGroup {
 public:
  virtual ~RankGroup() = default;
  virtual int rank() const = 0;
  virtual int size() const = 0;
  // values <- their sum over the ranks, added in rank order: the same bits on
  // every rank, and from run to run for a given number of ranks.
  virtual void Sum(double* values, size_t n) const = 0;
  virtual double Max(double value) const = 0;
  virtual bool Any(bool value) const = 0;
};

// The ranks of the solve in progress, or nullptr.
const RankGroup* SolveRanks();

// Installs `ranks` for its lifetime (not nested).
class ScopedSolveRanks {
 public:
  explicit ScopedSolveRanks(const RankGroup* ranks);
  ~ScopedSolveRanks();
  ScopedSolveRanks(const ScopedSolveRanks&) = delete;
  ScopedSolveRanks& operator=(const ScopedSolveRanks&) = delete;
};

// Every part summed across the ranks, in one message.
void SumAcrossRanks(std::initializer_list<std::span<double>> parts);
// Every layer-sized block of `a` and of `b` (either may be null) and `value`,
// in one message; returns the sum of `value`.
double SumAcrossRanks(std::vector<std::vector<double>>* a, std::vector<std::vector<double>>* b, double value);
// `parts` and `value` likewise.
double SumAcrossRanks(std::vector<std::span<double>> parts, double value);
double SumAcrossRanks(double value);
double MaxAcrossRanks(double value);
// True on every rank when it is true on any (a stop that all must make together).
bool AnyRank(bool value);

// View rows [first, first + count) that rank `rank` of `ranks` holds of `rows`:
// contiguous blocks, their sizes differing by at most one.
struct ViewRowBlock {
  int first = 0, count = 0;
};
ViewRowBlock ViewRowsOfRank(int rows, int rank, int ranks);

}  // namespace layerlab
