#include "layerlab/kernels/depth_sums_row.h"

#include "layerlab/framework/error.h"
#include "layerlab/kernels/joint_sums_ray.h"
#include "layerlab/kernels/row_kernels.h"
#include "layerlab/kernels/row_kernels_isa.h"
#include "layerlab/kernels/two_rays_avx2.h"
#include "layerlab/kernels/unrolled_layers.h"
#if LAYERLAB_ROW_KERNELS_AVX2
#include <immintrin.h>
#endif

namespace layerlab {
namespace {

// The squared error summed as SquaredErrorRow sums it: per channel in double, the rays of the pairs [0, pairs_end) on
// `even` and `odd` by parity and the rays after on `even`, then combined
// as (e0 + o0) + (e1 + o1) + (e2 + o2). The same double operations on each
// lane give its bits in both builds (tests check it).
struct ErrorSums {
  double even[4] = {}, odd[4] = {};
  int pairs_end = 0;  // SquaredErrorRow's pairs (j, j + 1) while j + 1 < safe

  ErrorSums(int cols, bool exact_last) {
    const int safe = exact_last ? cols - 1 : cols;
    pairs_end = safe < 0 ? 0 : safe / 2 * 2;
  }
  void Add(int j, Rgb4 t, Rgb4 l) {
    double* sums = j < pairs_end && j % 2 ? odd : even;
    for (int c = 0; c < 3; ++c) {
      const double d = double(t[c]) - double(l[c]);
      sums[c] += d * d;
    }
  }
  double Total() const { return (even[0] + odd[0]) + (even[1] + odd[1]) + (even[2] + odd[2]); }
};

// Rays [begin, cols), one at a time.
template <int L>
struct Baseline {
  static void Run(const Rgb4* const* rows, int branches, const int* a, const Rgb4* w, int begin, int cols,
                  const float* l, bool exact_last, ErrorSums* error, Rgb4* const* res, Rgb4* const* den) {
    const int safe = exact_last ? cols - 1 : cols;
    for (int j = begin; j < cols; ++j) {
      const Rgb4 lj = j < safe ? LoadRgbOver(l + j * 3) : LoadRgb(l + j * 3);
      Rgb4 light = {};
      for (int b = 0; b < branches; ++b) {
        Rgb4 p = w[b];
        for (int k = 0; k < L; ++k) p *= rows[b * L + k][j];
        light += p;
      }
      if (error) error->Add(j, lj, light);
      const Rgb4 residual = light - lj;
      for (int b = 0; b < branches; ++b) {
        const Rgb4* const* r = rows + b * L;
        if (!a) {  // every member
          Rgb4 v[L];
          for (int k = 0; k < L; ++k) v[k] = r[k][j];
          AddJointSumsOfRay<L>(v, w[b], residual, light, j, res + b * L, den + b * L);
          continue;
        }
        Rgb4 prefix = w[b];
        for (int k = 0; k < a[b]; ++k) prefix *= r[k][j];
        Rgb4 suffix = Rgb4{1, 1, 1, 1};
        for (int k = L - 1; k > a[b]; --k) suffix *= r[k][j];
        const Rgb4 q = prefix * suffix;
        res[b][j] += residual * q;
        den[b][j] += light * q;
      }
    }
  }
};

#if LAYERLAB_ROW_KERNELS_AVX2
#define LAYERLAB_AVX2 __attribute__((target("avx2")))

using avx2::LoadTwoRaysOver;
using avx2::Squared;
using avx2::Twice;

// Rays j and j + 1 of a padded row.
LAYERLAB_AVX2 inline __m256 TwoRays(const Rgb4* row, int j) {
  return _mm256_loadu_ps(reinterpret_cast<const float*>(row + j));
}

// Member ab's q of a branch whose layer values at the two rays are at(k).
// A product that starts from 1 starts from its first factor instead (1 x is x).
template <int L, class At>
LAYERLAB_AVX2 inline __m256 MemberQ(__m256 w2, int ab, At at) {
  __m256 q = w2;
  for (int k = 0; k < ab; ++k) q = _mm256_mul_ps(q, at(k));
  if constexpr (L > 1)
    if (ab < L - 1) {  // times the product of the members after ab, multiplied from the back
      __m256 suffix = at(L - 1);
      for (int k = L - 2; k > ab; --k) suffix = _mm256_mul_ps(suffix, at(k));
      q = _mm256_mul_ps(q, suffix);
    }
  return q;
}

// res += (light - l) q, den += light q at rays j, j + 1.
LAYERLAB_AVX2 inline void AddSums(__m256 residual, __m256 light, __m256 q, float* res, float* den) {
  _mm256_storeu_ps(res, _mm256_add_ps(_mm256_loadu_ps(res), _mm256_mul_ps(residual, q)));
  _mm256_storeu_ps(den, _mm256_add_ps(_mm256_loadu_ps(den), _mm256_mul_ps(light, q)));
}

// ErrorSums' even and odd sums of a pair of rays, one ray per register.
struct TwoRayErrors {
  __m256d even, odd;

  LAYERLAB_AVX2 void Add(__m256 lj, __m256 light) {
    even = _mm256_add_pd(even, Squared(Rgb4(_mm256_castps256_ps128(lj)), Rgb4(_mm256_castps256_ps128(light))));
    odd = _mm256_add_pd(odd, Squared(Rgb4(_mm256_extractf128_ps(lj, 1)), Rgb4(_mm256_extractf128_ps(light, 1))));
  }
  LAYERLAB_AVX2 void Into(ErrorSums* sums) const {
    _mm256_storeu_pd(sums->even, even), _mm256_storeu_pd(sums->odd, odd);
  }
};

// Two rays at a time, the same operations in the same order on each lane (no
// FMA: the file is built with -ffp-contract=off), so both builds give the same
// bits; each returns the first ray left, an even one below ErrorSums' pairs_end.

// K branches known at compile time: the pointers, weights and each ray's
// layer values stay in registers (2-3x the speed of the loop below). kAll:
// every member's sums (a null), else member a[b]'s of branch b.
template <int L, int K, bool kError, bool kAll>
LAYERLAB_AVX2 int FixedBranches(const Rgb4* const* rows, const int* a, const Rgb4* w, int cols, const float* l,
                                ErrorSums* error, Rgb4* const* res, Rgb4* const* den) {
  constexpr int kSums = kAll ? K * L : K;
  const float* r[K * L];
  float *n[kSums], *d[kSums];
  __m256 w2[K];
  int member[K];
  for (int s = 0; s < kSums; ++s) n[s] = reinterpret_cast<float*>(res[s]), d[s] = reinterpret_cast<float*>(den[s]);
  for (int b = 0; b < K; ++b) {
    for (int k = 0; k < L; ++k) r[b * L + k] = reinterpret_cast<const float*>(rows[b * L + k]);
    w2[b] = Twice(w[b]), member[b] = kAll ? 0 : a[b];
  }
  TwoRayErrors errors{_mm256_setzero_pd(), _mm256_setzero_pd()};
  int j = 0;
  for (; j + 3 <= cols; j += 2) {  // rays j, j + 1 read up to ray j + 2's green
    __m256 v[K][L];
    __m256 light = _mm256_setzero_ps();
    for (int b = 0; b < K; ++b) {
      __m256 p = w2[b];
      for (int k = 0; k < L; ++k) p = _mm256_mul_ps(p, v[b][k] = _mm256_loadu_ps(r[b * L + k] + j * 4));
      light = _mm256_add_ps(light, p);
    }
    const __m256 lj = LoadTwoRaysOver(l + j * 3);
    if constexpr (kError) errors.Add(lj, light);
    const __m256 residual = _mm256_sub_ps(light, lj);
    for (int b = 0; b < K; ++b) {
      if constexpr (kAll) {
        AddJointSumsOfTwoRays<L>(w2[b], v[b], residual, light, j, n + b * L, d + b * L);
      } else {
        const __m256 q = MemberQ<L>(w2[b], member[b], [&](int k) LAYERLAB_AVX2 { return v[b][k]; });
        AddSums(residual, light, q, n[b] + j * 4, d[b] + j * 4);
      }
    }
  }
  if constexpr (kError) errors.Into(error);
  return j;
}

// Any number of branches.
template <int L, bool kError>
LAYERLAB_AVX2 int AnyBranches(const Rgb4* const* rows, int branches, const int* a, const Rgb4* w, int cols,
                              const float* l, ErrorSums* error, Rgb4* const* res, Rgb4* const* den) {
  TwoRayErrors errors{_mm256_setzero_pd(), _mm256_setzero_pd()};
  int j = 0;
  for (; j + 3 <= cols; j += 2) {
    __m256 light = _mm256_setzero_ps();
    for (int b = 0; b < branches; ++b) {
      __m256 p = Twice(w[b]);
      for (int k = 0; k < L; ++k) p = _mm256_mul_ps(p, TwoRays(rows[b * L + k], j));
      light = _mm256_add_ps(light, p);
    }
    const __m256 lj = LoadTwoRaysOver(l + j * 3);
    if constexpr (kError) errors.Add(lj, light);
    const __m256 residual = _mm256_sub_ps(light, lj);
    for (int b = 0; b < branches; ++b) {
      if (!a) {
        __m256 v[L];
        float *n[L], *d[L];
        for (int k = 0; k < L; ++k) {
          v[k] = TwoRays(rows[b * L + k], j);
          n[k] = reinterpret_cast<float*>(res[b * L + k]), d[k] = reinterpret_cast<float*>(den[b * L + k]);
        }
        AddJointSumsOfTwoRays<L>(Twice(w[b]), v, residual, light, j, n, d);
        continue;
      }
      const __m256 q = MemberQ<L>(Twice(w[b]), a[b], [&](int k) LAYERLAB_AVX2 { return TwoRays(rows[b * L + k], j); });
      AddSums(residual, light, q, reinterpret_cast<float*>(res[b] + j), reinterpret_cast<float*>(den[b] + j));
    }
  }
  if constexpr (kError) errors.Into(error);
  return j;
}

template <int L, bool kError, bool kAll>
LAYERLAB_AVX2 int TwoRaysAtATime(const Rgb4* const* rows, int branches, const int* a, const Rgb4* w, int cols,
                                 const float* l, ErrorSums* error, Rgb4* const* res, Rgb4* const* den) {
  switch (branches) {
    case 1:
      return FixedBranches<L, 1, kError, kAll>(rows, a, w, cols, l, error, res, den);
    case 2:
      return FixedBranches<L, 2, kError, kAll>(rows, a, w, cols, l, error, res, den);
    case 3:
      return FixedBranches<L, 3, kError, kAll>(rows, a, w, cols, l, error, res, den);
    case 4:
      return FixedBranches<L, 4, kError, kAll>(rows, a, w, cols, l, error, res, den);
    default:
      return AnyBranches<L, kError>(rows, branches, a, w, cols, l, error, res, den);
  }
}

template <int L>
struct Avx2 {
  LAYERLAB_AVX2 static void Run(const Rgb4* const* rows, int branches, const int* a, const Rgb4* w, int cols,
                                const float* l, bool exact_last, ErrorSums* error, Rgb4* const* res, Rgb4* const* den) {
    const int j = error ? (a ? TwoRaysAtATime<L, true, false>(rows, branches, a, w, cols, l, error, res, den)
                             : TwoRaysAtATime<L, true, true>(rows, branches, a, w, cols, l, error, res, den))
                        : (a ? TwoRaysAtATime<L, false, false>(rows, branches, a, w, cols, l, error, res, den)
                             : TwoRaysAtATime<L, false, true>(rows, branches, a, w, cols, l, error, res, den));
    Baseline<L>::Run(rows, branches, a, w, j, cols, l, exact_last, error, res, den);
  }
};
#endif

// The baseline with its rays from 0.
template <int L>
struct WholeRow {
  static void Run(const Rgb4* const* rows, int branches, const int* a, const Rgb4* w, int cols, const float* l,
                  bool exact_last, ErrorSums* error, Rgb4* const* res, Rgb4* const* den) {
    Baseline<L>::Run(rows, branches, a, w, 0, cols, l, exact_last, error, res, den);
  }
};

}  // namespace

void DepthSumsRow(BranchRows branches, int cols, const int* a, PackedRow l, double* squared_error, MemberRowSums sums) {
  if (branches.stride != branches.layers) throw Error("DepthSumsRow: the branches' rows must follow one another");
  ErrorSums error_sums(cols, l.exact_last);
  ErrorSums* error = squared_error ? &error_sums : nullptr;
  const Rgb4* const* rows = branches.rows;
  const int count = branches.branches;
  const Rgb4* w = branches.w;
#if LAYERLAB_ROW_KERNELS_AVX2
  if (ActiveRowKernels() == RowKernelIsa::kAvx2)
    ForLayerCount<Avx2>(branches.layers, rows, count, a, w, cols, l.values, l.exact_last, error, sums.res, sums.den);
  else
#endif
    ForLayerCount<WholeRow>(branches.layers, rows, count, a, w, cols, l.values, l.exact_last, error, sums.res,
                            sums.den);
  if (squared_error) *squared_error = error_sums.Total();
}

}  // namespace layerlab
