// The ranks of a partitioned solve (`mpirun -np N layerlab solve`,
// docs/mpi.md): each rank holds a tile of the rays (RayTileOfRank), and every sum over
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

// The part of values[begin, end) that a rank sends in a reduction: from its
// first to its last value that is not +0.0 (a rank's rays reach a band of each
// layer's rows, and its sums elsewhere are exact zeros, which add nothing).
// {offset from begin, count}; {0, 0} when all are +0.0.
struct Span {
  size_t first = 0, count = 0;
};
Span NonzeroSpan(const double* values, size_t begin, size_t end);

// The rays rank `rank` of `ranks` holds of a light field of `view_rows` view
// rows of `pixel_rows` pixel rows each: a tile of whole view rows by whole
// pixel rows (every view column, every pixel column). The ranks form a grid of
// view_blocks x pixel_blocks tiles, rank = view block x pixel_blocks + pixel
// block, chosen so that the largest tile has the fewest rays (on a tie the
// more pixel blocks: a band of pixel rows reaches fewer layer rows); along an
// axis the blocks differ by at most one row. Throws when no grid of `ranks`
// tiles fits (more blocks along an axis than it has rows).
struct RayTile {
  int first_view_row = 0, view_rows = 0, first_pixel_row = 0, pixel_rows = 0;
  int view_blocks = 1, pixel_blocks = 1;
};
RayTile RayTileOfRank(int view_rows, int pixel_rows, int rank, int ranks);

}  // namespace layerlab
