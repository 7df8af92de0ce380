// Two rays per 256-bit register, one Rgb4 lane each: the loads and stores
// every AVX2 row kernel shares (row_kernels_avx2.cpp, kernels/depth_sums_row.cpp).
// Each function carries the avx2 target itself: call them only from code
// built for AVX2 (CpuHasAvx2()), hence the avx2 namespace.
#pragma once

#include "layerlab/kernels/row_kernels_isa.h"

#if LAYERLAB_ROW_KERNELS_AVX2
#include <immintrin.h>

#include "layerlab/framework/rgb4.h"

namespace layerlab::avx2 {

// Rays j and j + 1 of a packed row as two Rgb4 lanes, each with the next
// float in lane 3 as LoadRgbOver reads it: p[0..7] must be readable.
__attribute__((target("avx2"))) inline __m256 LoadTwoRaysOver(const float* p) {
  return _mm256_permutevar8x32_ps(_mm256_loadu_ps(p), _mm256_setr_epi32(0, 1, 2, 3, 3, 4, 5, 6));
}

// Two Rgb4 lanes as six packed floats, then two floats of padding: writes p[0..7].
__attribute__((target("avx2"))) inline void StoreTwoRaysOver(__m256 v, float* p) {
  _mm256_storeu_ps(p, _mm256_permutevar8x32_ps(v, _mm256_setr_epi32(0, 1, 2, 4, 5, 6, 7, 7)));
}

// v in both lanes.
__attribute__((target("avx2"))) inline __m256 Twice(Rgb4 v) { return _mm256_set_m128(__m128(v), __m128(v)); }

// One ray's (target - light)^2 in four doubles (lane 3 padding, never read).
__attribute__((target("avx2"))) inline __m256d Squared(Rgb4 t, Rgb4 l) {
  const __m256d diff = _mm256_sub_pd(_mm256_cvtps_pd(__m128(t)), _mm256_cvtps_pd(__m128(l)));
  return _mm256_mul_pd(diff, diff);
}

}  // namespace layerlab::avx2
#endif
