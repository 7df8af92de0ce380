// Random rows and the comparison of the row kernels' two builds, for the
// kernel tests (row_kernels_test.cpp, depth_sums_row_test.cpp).
#pragma once

#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <vector>

#include "layerlab/framework/rgb4.h"
#include "layerlab/kernels/row_kernels.h"

namespace layerlab {

constexpr float kGuard = 12345.0f;  // written past a row's end: must survive

struct Row {
  std::vector<float> packed;  // [ray][rgb], then one guard float
  std::vector<Rgb4> padded;   // [ray][rgb, 0]
};

inline Row RandomRow(int cols, std::mt19937& rng, float lo = 0.0f, float hi = 1.0f) {
  std::uniform_real_distribution<float> u(lo, hi);
  Row r;
  for (int j = 0; j < cols * 3; ++j) r.packed.push_back(u(rng));
  r.packed.push_back(u(rng));  // the over-read float a row's last ray may read when exact_last is false
  for (int j = 0; j < cols; ++j) r.padded.push_back(Rgb4{u(rng), u(rng), u(rng), 0.0f});
  return r;
}

inline bool SameBits(const void* a, const void* b, size_t bytes) { return std::memcmp(a, b, bytes) == 0; }

// Runs `f` with each build; `f` returns what it computed as bytes.
template <typename F>
void ExpectSameInBothBuilds(F f, const char* what, int cols) {
  // The checks against the plain loops still run (and fail the test if they
  // fail); the test is reported as skipped, not passed, without the comparison.
  if (!CpuHasAvx2()) GTEST_SKIP() << "this CPU lacks AVX2: the AVX2 build of " << what << " was not compared";
  ASSERT_TRUE(ForceRowKernels(RowKernelIsa::kBaseline));
  const std::vector<unsigned char> base = f();
  ASSERT_TRUE(ForceRowKernels(RowKernelIsa::kAvx2));
  const std::vector<unsigned char> avx = f();
  EXPECT_TRUE(base.size() == avx.size() && SameBits(base.data(), avx.data(), base.size()))
      << what << ", " << cols << " rays";
}

template <typename T>
std::vector<unsigned char> Bytes(const std::vector<T>& v) {
  std::vector<unsigned char> b(v.size() * sizeof(T));
  if (!b.empty()) std::memcpy(b.data(), v.data(), b.size());
  return b;
}

}  // namespace layerlab
