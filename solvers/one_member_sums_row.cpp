#include "solvers/one_member_sums_row.h"

#include "systems/row_kernels.h"
#include "systems/row_kernels_isa.h"
#include "systems/unrolled_layers.h"
#if LAYERLAB_ROW_KERNELS_AVX2
#include <immintrin.h>
#endif

namespace layerlab {
namespace {

// One ray, as JointSumsRay forms member a's q.
template <int L>
inline void Ray(const Rgb4* const* r, int a, Rgb4 w, int j, Rgb4 lj, const Rgb4* light, Rgb4* num, Rgb4* den) {
  Rgb4 prefix = w;
  for (int k = 0; k < a; ++k) prefix *= r[k][j];
  Rgb4 suffix = Rgb4{1, 1, 1, 1};
  for (int k = L - 1; k > a; --k) suffix *= r[k][j];
  const Rgb4 q = prefix * suffix;
  num[j] += lj * q;
  den[j] += light[j] * q;
}

template <int L>
struct Baseline {
  static void Run(const Rgb4* const* rows, int a, Rgb4 w, int cols, const float* l, bool exact_last, const Rgb4* light,
                  Rgb4* num, Rgb4* den) {
    const int safe = exact_last ? cols - 1 : cols;
    for (int j = 0; j < cols; ++j)
      Ray<L>(rows, a, w, j, j < safe ? LoadRgbOver(l + j * 3) : LoadRgb(l + j * 3), light, num, den);
  }
};

#if LAYERLAB_ROW_KERNELS_AVX2
#define LAYERLAB_AVX2 __attribute__((target("avx2")))

// Two rays, the same operations in the same order on each lane (no FMA: the
// file is built with -ffp-contract=off), so both builds give the same bits.
template <int L>
struct Avx2 {
  LAYERLAB_AVX2 static void Run(const Rgb4* const* rows, int a, Rgb4 w, int cols, const float* l, bool exact_last,
                                const Rgb4* light, Rgb4* num, Rgb4* den) {
    const float* r[L];
    for (int k = 0; k < L; ++k) r[k] = reinterpret_cast<const float*>(rows[k]);
    float* n = reinterpret_cast<float*>(num);
    float* d = reinterpret_cast<float*>(den);
    const float* li = reinterpret_cast<const float*>(light);
    const __m256 w2 = _mm256_set_m128(__m128(w), __m128(w)), ones = _mm256_set1_ps(1.0f);
    // Rays j and j + 1 of the packed l, each with the next float in lane 3 as LoadRgbOver reads it.
    const __m256i spread = _mm256_setr_epi32(0, 1, 2, 3, 3, 4, 5, 6);
    int j = 0;
    for (; j + 3 <= cols; j += 2) {  // rays j, j + 1 read up to ray j + 2's green
      __m256 prefix = w2;
      for (int k = 0; k < a; ++k) prefix = _mm256_mul_ps(prefix, _mm256_loadu_ps(r[k] + j * 4));
      __m256 suffix = ones;
      for (int k = L - 1; k > a; --k) suffix = _mm256_mul_ps(suffix, _mm256_loadu_ps(r[k] + j * 4));
      const __m256 q = _mm256_mul_ps(prefix, suffix);
      const __m256 lj = _mm256_permutevar8x32_ps(_mm256_loadu_ps(l + j * 3), spread);
      _mm256_storeu_ps(n + j * 4, _mm256_add_ps(_mm256_loadu_ps(n + j * 4), _mm256_mul_ps(lj, q)));
      _mm256_storeu_ps(d + j * 4,
                       _mm256_add_ps(_mm256_loadu_ps(d + j * 4), _mm256_mul_ps(_mm256_loadu_ps(li + j * 4), q)));
    }
    const Rgb4* rest[L];
    for (int k = 0; k < L; ++k) rest[k] = rows[k] + j;
    Baseline<L>::Run(rest, a, w, cols - j, l + j * 3, exact_last, light + j, num + j, den + j);
  }
};
#endif

}  // namespace

void OneMemberSumsRow(const Rgb4* const* rows, int layers, int a, Rgb4 w, int cols, const float* l, bool exact_last,
                      const Rgb4* light, Rgb4* num, Rgb4* den) {
#if LAYERLAB_ROW_KERNELS_AVX2
  if (ActiveRowKernels() == RowKernelIsa::kAvx2)
    return ForLayerCount<Avx2>(layers, rows, a, w, cols, l, exact_last, light, num, den);
#endif
  ForLayerCount<Baseline>(layers, rows, a, w, cols, l, exact_last, light, num, den);
}

}  // namespace layerlab
