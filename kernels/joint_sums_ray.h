// The joint pass's sums of every member a of one branch of L layers at one
// ray (or, in the AVX2 build, two rays), q_a = w prod_{k != a} v[k]:
//   res[a][j] += residual q_a,  den[a][j] += light q_a,
// q_a multiplied from the front up to a and from the back down to it. One
// home for JointSumsRow (row_kernels.h) and DepthSumsRow
// (kernels/depth_sums_row.h): the same operations in the same order in
// both, so their sums have the same bits.
#pragma once

#include "layerlab/framework/rgb4.h"
#include "layerlab/kernels/row_kernels_isa.h"
#if LAYERLAB_ROW_KERNELS_AVX2
#include <immintrin.h>
#endif

namespace layerlab {

// v[k]: member k's value at ray j; res, den: [member] rows.
template <int L>
inline void AddJointSumsOfRay(const Rgb4* v, Rgb4 w, Rgb4 residual, Rgb4 light, int j, Rgb4* const* res,
                              Rgb4* const* den) {
  Rgb4 prefix[L];  // w times the members before a
  Rgb4 p = w;
  for (int k = 0; k < L; ++k) prefix[k] = p, p *= v[k];
  Rgb4 suffix = Rgb4{1, 1, 1, 1};  // the members after a
  for (int a = L - 1; a >= 0; --a) {
    const Rgb4 q = prefix[a] * suffix;
    res[a][j] += residual * q;
    den[a][j] += light * q;
    suffix *= v[a];
  }
}

#if LAYERLAB_ROW_KERNELS_AVX2
// Rays j and j + 1, two Rgb4 lanes per register; w2 = w in both lanes; res,
// den: [member] rows as floats. A product that starts from 1 starts from its
// first factor instead (1 x is x), so the bits are AddJointSumsOfRay's.
template <int L>
__attribute__((target("avx2"))) inline void AddJointSumsOfTwoRays(__m256 w2, const __m256* v, __m256 residual,
                                                                  __m256 light, int j, float* const* res,
                                                                  float* const* den) {
  auto add = [&](__m256 q, int a) __attribute__((target("avx2"))) {
    float* r = res[a] + j * 4;
    float* d = den[a] + j * 4;
    _mm256_storeu_ps(r, _mm256_add_ps(_mm256_loadu_ps(r), _mm256_mul_ps(residual, q)));
    _mm256_storeu_ps(d, _mm256_add_ps(_mm256_loadu_ps(d), _mm256_mul_ps(light, q)));
  };
  __m256 prefix[L];
  __m256 p = w2;
  for (int k = 0; k < L; ++k) prefix[k] = p, p = _mm256_mul_ps(p, v[k]);
  add(prefix[L - 1], L - 1);
  if constexpr (L > 1) {
    __m256 suffix = v[L - 1];
    for (int a = L - 2; a >= 0; --a) {
      add(_mm256_mul_ps(prefix[a], suffix), a);
      if (a > 0) suffix = _mm256_mul_ps(suffix, v[a]);
    }
  }
}
#endif

}  // namespace layerlab
