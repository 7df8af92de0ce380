#include "layerlab/framework/mpi_ranks.h"

#include <bit>
#include <cassert>
#include <cstdint>
#include <string>
#include <tuple>
#include <utility>

#include "layerlab/framework/error.h"

namespace layerlab {
namespace {
const RankGroup* g_ranks = nullptr;

// Packed into one message, summed, and unpacked.
void SumParts(std::span<const std::span<double>> parts) {
  if (!g_ranks) return;
  size_t n = 0;
  for (std::span<double> part : parts) n += part.size();
  static std::vector<double> packed;  // kept: a fresh block would fault its pages in on every sum
  packed.clear();
  packed.reserve(n);
  for (std::span<double> part : parts) packed.insert(packed.end(), part.begin(), part.end());
  g_ranks->Sum(packed.data(), packed.size());
  const double* next = packed.data();
  for (std::span<double> part : parts)
    for (double& v : part) v = *next++;
}

}  // namespace

const RankGroup* SolveRanks() { return g_ranks; }

ScopedSolveRanks::ScopedSolveRanks(const RankGroup* ranks) {
  assert(g_ranks == nullptr);
  g_ranks = ranks;
}
ScopedSolveRanks::~ScopedSolveRanks() { g_ranks = nullptr; }

void SumAcrossRanks(std::initializer_list<std::span<double>> parts) {
  SumParts(std::span<const std::span<double>>(parts.begin(), parts.size()));
}

double SumAcrossRanks(std::vector<std::vector<double>>* a, std::vector<std::vector<double>>* b, double value) {
  if (!g_ranks) return value;
  std::vector<std::span<double>> parts;
  for (std::vector<std::vector<double>>* blocks : {a, b})
    if (blocks) parts.insert(parts.end(), blocks->begin(), blocks->end());
  parts.emplace_back(&value, 1);
  SumParts(parts);
  return value;
}

double SumAcrossRanks(std::vector<std::span<double>> parts, double value) {
  if (!g_ranks) return value;
  parts.emplace_back(&value, 1);
  SumParts(parts);
  return value;
}

double SumAcrossRanks(double value) {
  if (g_ranks) g_ranks->Sum(&value, 1);
  return value;
}

double MaxAcrossRanks(double value) { return g_ranks ? g_ranks->Max(value) : value; }

bool AnyRank(bool value) { return g_ranks ? g_ranks->Any(value) : value; }

Span NonzeroSpan(const double* values, size_t begin, size_t end) {
  const size_t start = begin;
  auto zero = [&](size_t k) { return std::bit_cast<uint64_t>(values[k]) == 0; };  // +0.0 alone: -0.0 would add
  while (begin < end && zero(begin)) ++begin;
  while (end > begin && zero(end - 1)) --end;
  return {begin - start, end - begin};
}

namespace {

// Block `block` of `blocks` contiguous blocks of `rows` rows, their sizes one apart: {first, count}.
std::pair<int, int> EvenBlock(int rows, int block, int blocks) {
  const long first = long(rows) * block / blocks, end = long(rows) * (block + 1) / blocks;
  return {static_cast<int>(first), static_cast<int>(end - first)};
}

}  // namespace

RayTile RayTileOfRank(int view_rows, int pixel_rows, int rank, int ranks) {
  if (ranks < 1 || rank < 0 || rank >= ranks || view_rows < 1 || pixel_rows < 1)
    throw Error("internal error: rank " + std::to_string(rank) + " of " + std::to_string(ranks) + " for " +
                std::to_string(view_rows) + " x " + std::to_string(pixel_rows) + " rows");
  RayTile tile;
  long fewest = -1;
  for (int a = 1; a <= ranks; ++a) {  // a view blocks of b pixel blocks
    const int b = ranks / a;
    if (ranks % a != 0 || a > view_rows || b > pixel_rows) continue;
    const long largest = long((view_rows + a - 1) / a) * ((pixel_rows + b - 1) / b);
    if (fewest < 0 || largest < fewest) fewest = largest, tile.view_blocks = a, tile.pixel_blocks = b;
  }
  if (fewest < 0)
    throw Error(std::to_string(ranks) + " MPI ranks cannot share " + std::to_string(view_rows) + " view rows of " +
                std::to_string(pixel_rows) + " pixel rows: each rank holds a tile of a grid of view-row blocks by " +
                "pixel-row blocks, so the rank count must be a x b with a <= " + std::to_string(view_rows) +
                " and b <= " + std::to_string(pixel_rows));
  std::tie(tile.first_view_row, tile.view_rows) = EvenBlock(view_rows, rank / tile.pixel_blocks, tile.view_blocks);
  std::tie(tile.first_pixel_row, tile.pixel_rows) = EvenBlock(pixel_rows, rank % tile.pixel_blocks, tile.pixel_blocks);
  return tile;
}

}  // namespace layerlab
