#include "layerlab/framework/mpi_ranks.h"

#include <cassert>

namespace layerlab {
namespace {
const RankGroup* g_ranks = nullptr;

// Packed into one message, summed, and unpacked.
void SumParts(std::span<const std::span<double>> parts) {
  if (!g_ranks) return;
  size_t n = 0;
  for (std::span<double> part : parts) n += part.size();
  std::vector<double> packed;
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

ViewRowBlock ViewRowsOfRank(int rows, int rank, int ranks) {
  const long first = long(rows) * rank / ranks, end = long(rows) * (rank + 1) / ranks;
  return {static_cast<int>(first), static_cast<int>(end - first)};
}

}  // namespace layerlab
