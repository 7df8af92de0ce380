// Sweeps over n values in kSweepChunks fixed chunks, for solvers whose work
// vectors are a few MB (quasi-newton's L-BFGS vectors, 8 MB each at paper
// scale): one parallel region per sweep does an element-wise body over
// every chunk and any number of sums over the values, so that a step makes
// a few sweeps instead of one per operation.
//
// The sums are the same bits for any thread count: chunk c's sum adds
// terms(i) in index order, the chunks' sums are added in chunk order. A
// chunk's sum is one chain of dependent adds (four cycles each), so a
// thread runs up to kSweepInterleaved chunks' chains side by side, block
// by block (kSweepBlock values of each chunk), each block's body first;
// bodies are element-wise (each value's result does not depend on the
// order the values are visited in). Fewer chunks run side by side where
// there are too many threads to share the groups evenly.
#pragma once

#include <omp.h>

#include <algorithm>
#include <array>
#include <cstddef>

namespace layerlab {

constexpr size_t kSweepChunks = 64;
constexpr size_t kSweepInterleaved = 4;
constexpr size_t kSweepBlock = 4096;  // values per chunk and block: a few vectors' blocks stay in L2

namespace detail {

// Sweep's groups of kInterleaved chunks each, side by side; part[c] = chunk c's sums.
template <size_t kInterleaved, size_t kTerms, class Body, class... Terms>
void SweepGroups(size_t n, Body& body, std::array<std::array<double, kTerms>, kSweepChunks>* part, Terms&... terms) {
#pragma omp parallel for schedule(static)
  for (size_t group = 0; group < kSweepChunks / kInterleaved; ++group) {
    size_t begin[kInterleaved], end[kInterleaved], longest = 0;
    for (size_t u = 0; u < kInterleaved; ++u) {
      const size_t c = group * kInterleaved + u;
      begin[u] = n * c / kSweepChunks, end[u] = n * (c + 1) / kSweepChunks;
      longest = std::max(longest, end[u] - begin[u]);
    }
    std::array<std::array<double, kTerms>, kInterleaved> sum{};
    auto add = [&]([[maybe_unused]] size_t u, [[maybe_unused]] size_t i) {
      [[maybe_unused]] size_t k = 0;
      ((sum[u][k++] += terms(i)), ...);
    };
    for (size_t offset = 0; offset < longest; offset += kSweepBlock) {
      size_t stop[kInterleaved], common = kSweepBlock;  // common: the length every chunk has in this block
      for (size_t u = 0; u < kInterleaved; ++u) {
        const size_t from = std::min(begin[u] + offset, end[u]);
        stop[u] = std::min(from + kSweepBlock, end[u]);
        if (from < stop[u]) body(from, stop[u]);
        common = std::min(common, stop[u] - from);
      }
      if constexpr (kTerms > 0) {
        for (size_t i = 0; i < common; ++i)
          for (size_t u = 0; u < kInterleaved; ++u) add(u, begin[u] + offset + i);
        for (size_t u = 0; u < kInterleaved; ++u)  // a longer chunk's last values
          for (size_t i = begin[u] + offset + common; i < stop[u]; ++i) add(u, i);
      }
    }
    for (size_t u = 0; u < kInterleaved; ++u) (*part)[group * kInterleaved + u] = sum[u];
  }
}

}  // namespace detail

// body(begin, end) over blocks that together cover [0, n) once; returns
// the sums of each of terms(i) over [0, n), each taken after body has run
// over value i.
template <class Body, class... Terms>
std::array<double, sizeof...(Terms)> Sweep(size_t n, Body body, Terms... terms) {
  constexpr size_t kTerms = sizeof...(Terms);
  std::array<std::array<double, kTerms>, kSweepChunks> part{};
  // At least four groups per thread: four chunks side by side on up to 4 threads, two on up to 8, else one.
  const size_t threads = static_cast<size_t>(std::max(omp_get_max_threads(), 1));
  if (kSweepChunks / kSweepInterleaved >= 4 * threads)
    detail::SweepGroups<kSweepInterleaved>(n, body, &part, terms...);
  else if (kSweepChunks / 2 >= 4 * threads)
    detail::SweepGroups<2>(n, body, &part, terms...);
  else
    detail::SweepGroups<1>(n, body, &part, terms...);
  std::array<double, kTerms> total{};
  for (const auto& p : part)
    for (size_t k = 0; k < kTerms; ++k) total[k] += p[k];
  return total;
}

// A body that runs body(i) for each value i of a block.
template <class Body>
auto Each(Body body) {
  return [body](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) body(i);
  };
}

}  // namespace layerlab
