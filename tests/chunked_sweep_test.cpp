// solvers/chunked_sweep.h: a sweep's sums are the chunked sums added one
// value at a time, bit for bit, on any thread count; its body runs once
// per value, before the terms read it.
#include "layerlab/solvers/chunked_sweep.h"

#include <gtest/gtest.h>
#include <omp.h>

#include <array>
#include <cmath>
#include <random>
#include <vector>

namespace layerlab {
namespace {

// The sums as written down: chunk by chunk, value by value, in double.
double ChunkedReference(const std::vector<double>& a, const std::vector<double>& b) {
  const size_t n = a.size();
  double total = 0;
  for (size_t c = 0; c < kSweepChunks; ++c) {
    double sum = 0;
    for (size_t i = n * c / kSweepChunks; i < n * (c + 1) / kSweepChunks; ++i) sum += a[i] * b[i];
    total += sum;
  }
  return total;
}

// Values over many orders of magnitude and both signs: any other order of adds changes the bits.
std::vector<double> Scattered(size_t n, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> mantissa(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-20, 20);
  std::vector<double> v(n);
  for (double& x : v) x = std::ldexp(mantissa(random), exponent(random));
  return v;
}

// Sizes below a chunk per thread, at and around the chunk and block edges, and chunks of unequal lengths.
const size_t kSizes[] = {0,
                         1,
                         3,
                         63,
                         64,
                         65,
                         255,
                         256,
                         257,
                         kSweepBlock* kSweepChunks - 1,
                         kSweepBlock* kSweepChunks,
                         kSweepBlock* kSweepChunks + 37,
                         3 * kSweepBlock* kSweepChunks + 1001};

class ThreadCount {
 public:
  explicit ThreadCount(int threads) : saved_(omp_get_max_threads()) { omp_set_num_threads(threads); }
  ~ThreadCount() { omp_set_num_threads(saved_); }

 private:
  int saved_;
};

TEST(ChunkedSweep, SumsAreTheChunkedSumsBitForBitOnAnyThreadCount) {
  for (size_t n : kSizes) {
    const std::vector<double> a = Scattered(n, 1), b = Scattered(n, 2);
    const double expected = ChunkedReference(a, b);
    for (int threads : {1, 2, 3}) {
      ThreadCount scope(threads);
      const double got = Sweep(
          n, [](size_t, size_t) {}, [&](size_t i) { return a[i] * b[i]; })[0];
      EXPECT_EQ(got, expected) << "n = " << n << ", " << threads << " threads";
      // Four, two and one chunks side by side (Sweep takes fewer on many threads).
      auto body = [](size_t, size_t) {};
      auto term = [&](size_t i) { return a[i] * b[i]; };
      std::array<std::array<double, 1>, kSweepChunks> p4{}, p2{}, p1{};
      detail::SweepGroups<4>(n, body, &p4, term);
      detail::SweepGroups<2>(n, body, &p2, term);
      detail::SweepGroups<1>(n, body, &p1, term);
      double t4 = 0, t2 = 0, t1 = 0;
      for (size_t c = 0; c < kSweepChunks; ++c) t4 += p4[c][0], t2 += p2[c][0], t1 += p1[c][0];
      EXPECT_EQ(t4, expected) << n;
      EXPECT_EQ(t2, expected) << n;
      EXPECT_EQ(t1, expected) << n;
    }
  }
}

TEST(ChunkedSweep, SeveralSumsInOneSweepAreEachAlone) {
  const size_t n = kSweepBlock * kSweepChunks + 37;
  const std::vector<double> a = Scattered(n, 3), b = Scattered(n, 4), c = Scattered(n, 5);
  const auto [ab, bc, aa] = Sweep(
      n, [](size_t, size_t) {}, [&](size_t i) { return a[i] * b[i]; }, [&](size_t i) { return b[i] * c[i]; },
      [&](size_t i) { return a[i] * a[i]; });
  EXPECT_EQ(ab, ChunkedReference(a, b));
  EXPECT_EQ(bc, ChunkedReference(b, c));
  EXPECT_EQ(aa, ChunkedReference(a, a));
}

TEST(ChunkedSweep, BodyRunsOncePerValueBeforeTheTermsReadIt) {
  for (size_t n : kSizes) {
    const std::vector<double> a = Scattered(n, 6), b = Scattered(n, 7);
    std::vector<double> q(n, 0.0);
    std::vector<int> visits(n, 0);
    // q = a (once), then the sum of q b: the reference's a . b only if every q was written before it was read.
    const double got = Sweep(n, Each([&](size_t i) {
                               q[i] += a[i];
                               ++visits[i];
                             }),
                             [&](size_t i) { return q[i] * b[i]; })[0];
    EXPECT_EQ(got, ChunkedReference(a, b)) << "n = " << n;
    for (size_t i = 0; i < n; ++i) ASSERT_EQ(visits[i], 1) << "value " << i << " of " << n;
    // A sweep of no sums: the body alone, once per value.
    Sweep(n, Each([&](size_t i) { ++visits[i]; }));
    for (size_t i = 0; i < n; ++i) ASSERT_EQ(visits[i], 2) << "value " << i << " of " << n;
  }
}

}  // namespace
}  // namespace layerlab
