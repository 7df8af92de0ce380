// Sweeps over n values in kSweepChunks fixed chunks, for solvers whose work
// vectors are a few MB (quasi-newton's L-BFGS vectors, 8 MB each at paper
// scale): one parallel region per sweep does an element-wise body over
// every chunk and any number of sums over the values, so that a step makes
// a few sweeps instead of one per operation.
//
// The sums are the same bits for any thread count: chunk c's sum adds
// terms(i) in index order, the chunks' sums are added in chunk order. A
// chunk's sum is one chain of dependent adds (four cycles each), so a
// thread runs kSweepInterleaved chunks' chains side by side, block by
// block, each block's body first; bodies are element-wise (each value's
// result does not depend on the order the values are visited in).
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>

namespace layerlab {

constexpr size_t kSweepChunks = 64;
constexpr size_t kSweepInterleaved = 4;
constexpr size_t kSweepBlock = 4096;  // values per chunk and block: a few vectors' blocks stay in L2

// body(begin, end) over every chunk; returns the sums of each of terms(i)
// over [0, n), each taken after body has run over value i.
template <class Body, class... Terms>
std::array<double, sizeof...(Terms)> Sweep(size_t n, Body body, Terms... terms) {
  constexpr size_t kTerms = sizeof...(Terms);
  std::array<std::array<double, kTerms>, kSweepChunks> part{};
#pragma omp parallel for schedule(static)
  for (size_t group = 0; group < kSweepChunks / kSweepInterleaved; ++group) {
    size_t begin[kSweepInterleaved], end[kSweepInterleaved], longest = 0;
    for (size_t u = 0; u < kSweepInterleaved; ++u) {
      const size_t c = group * kSweepInterleaved + u;
      begin[u] = n * c / kSweepChunks, end[u] = n * (c + 1) / kSweepChunks;
      longest = std::max(longest, end[u] - begin[u]);
    }
    std::array<std::array<double, kTerms>, kSweepInterleaved> sum{};
    auto add = [&]([[maybe_unused]] size_t u, [[maybe_unused]] size_t i) {
      [[maybe_unused]] size_t k = 0;
      ((sum[u][k++] += terms(i)), ...);
    };
    for (size_t offset = 0; offset < longest; offset += kSweepBlock) {
      size_t stop[kSweepInterleaved], common = kSweepBlock;  // common: the length every chunk has in this block
      for (size_t u = 0; u < kSweepInterleaved; ++u) {
        const size_t from = std::min(begin[u] + offset, end[u]);
        stop[u] = std::min(from + kSweepBlock, end[u]);
        if (from < stop[u]) body(from, stop[u]);
        common = std::min(common, stop[u] - from);
      }
      if constexpr (kTerms > 0) {
        for (size_t i = 0; i < common; ++i)
          for (size_t u = 0; u < kSweepInterleaved; ++u) add(u, begin[u] + offset + i);
        for (size_t u = 0; u < kSweepInterleaved; ++u)  // a longer chunk's last values
          for (size_t i = begin[u] + offset + common; i < stop[u]; ++i) add(u, i);
      }
    }
    for (size_t u = 0; u < kSweepInterleaved; ++u) part[group * kSweepInterleaved + u] = sum[u];
  }
  std::array<double, kTerms> total{};
  for (const auto& p : part)
    for (size_t k = 0; k < kTerms; ++k) total[k] += p[k];
  return total;
}

// A body that runs body(i) for each value i of a chunk.
template <class Body>
auto Each(Body body) {
  return [body](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) body(i);
  };
}

}  // namespace layerlab
