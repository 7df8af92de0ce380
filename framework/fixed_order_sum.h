// A long sum in double that has the same bits on any thread count: the terms
// are summed in fixed chunks, each in order on one thread, and the chunks'
// sums in chunk order. (An OpenMP reduction adds its threads' partial sums
// in an unspecified order, so its last bits vary with the thread count.)
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

namespace layerlab {

inline constexpr size_t kFixedOrderSumChunk = size_t(1) << 14;

// sum of term(i) for i in [0, n).
template <class Term>
double FixedOrderSum(size_t n, Term term) {
  const size_t chunks = (n + kFixedOrderSumChunk - 1) / kFixedOrderSumChunk;
  std::vector<double> partial(chunks);
#pragma omp parallel for schedule(static)
  for (size_t c = 0; c < chunks; ++c) {
    const size_t end = std::min(n, (c + 1) * kFixedOrderSumChunk);
    double sum = 0;
    for (size_t i = c * kFixedOrderSumChunk; i < end; ++i) sum += term(i);
    partial[c] = sum;
  }
  double total = 0;
  for (double p : partial) total += p;
  return total;
}

// sum of (a[i] - b[i])^2 in double.
inline double FixedOrderSquaredDifference(const float* a, const float* b, size_t n) {
  return FixedOrderSum(n, [a, b](size_t i) {
    const double e = double(a[i]) - b[i];
    return e * e;
  });
}

}  // namespace layerlab
