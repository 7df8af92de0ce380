// The AVX2 build of row_kernels.h: two rays per 256-bit instruction where the
// baseline takes one, the same operations in the same order on every lane
// (no FMA), so that both builds give the same bits. Per function target
// attributes rather than -mavx2 for the file: inline functions of shared
// headers compiled here must not replace the baseline's copies at link time.
// The rays a two-ray step leaves at a row's end go to the baseline itself,
// except in the error sums, whose even/odd partial sums must carry on.
#include "layerlab/kernels/row_kernels_isa.h"

#if LAYERLAB_ROW_KERNELS_AVX2

#include <immintrin.h>

#include <type_traits>

#include "layerlab/kernels/joint_sums_ray.h"
#include "layerlab/kernels/two_rays_avx2.h"
#include "layerlab/kernels/unrolled_layers.h"

#define LAYERLAB_AVX2 __attribute__((target("avx2")))

namespace layerlab::avx2 {
namespace {

template <int L>
struct AddBranchLightRowOf {
  LAYERLAB_AVX2 static void Run(const Rgb4* const* rows, Rgb4 w, int cols, Rgb4* row) {
    const float* r[L];
    for (int k = 0; k < L; ++k) r[k] = reinterpret_cast<const float*>(rows[k]);
    float* out = reinterpret_cast<float*>(row);
    const __m256 w2 = Twice(w);
    int j = 0;
    for (; j + 1 < cols; j += 2) {
      __m256 p = w2;
      for (int k = 0; k < L; ++k) p = _mm256_mul_ps(p, _mm256_loadu_ps(r[k] + j * 4));
      _mm256_storeu_ps(out + j * 4, _mm256_add_ps(_mm256_loadu_ps(out + j * 4), p));
    }
    const Rgb4* rest[L];
    for (int k = 0; k < L; ++k) rest[k] = rows[k] + j;
    baseline::AddBranchLightRow({rest, L, w, cols - j}, row + j);
  }
};

// G terms of L layers each over two rays at a time, the running sum in a register.
template <int L, int G>
LAYERLAB_AVX2 void AddTermsGroup(const Rgb4* const* rows, int stride, const Rgb4* w, int begin, int end, Rgb4* row) {
  const float* r[G][L];
  __m256 w2[G];
  for (int g = 0; g < G; ++g) {
    w2[g] = Twice(w[g]);
    for (int k = 0; k < L; ++k) r[g][k] = reinterpret_cast<const float*>(rows[g * stride + k]);
  }
  float* out = reinterpret_cast<float*>(row);
  int j = begin;
  for (; j + 1 < end; j += 2) {
    __m256 sum = _mm256_loadu_ps(out + j * 4);
    for (int g = 0; g < G; ++g) {
      __m256 p = w2[g];
      for (int k = 0; k < L; ++k) p = _mm256_mul_ps(p, _mm256_loadu_ps(r[g][k] + j * 4));
      sum = _mm256_add_ps(sum, p);
    }
    _mm256_storeu_ps(out + j * 4, sum);
  }
  if (j < end) baseline::AddBranchLightTermsRow({rows, stride, L, w, G}, j, end, row);
}

// group(std::integral_constant<int, G>, first) over [0, count) in order: groups
// of four (their pointers and weights fit in registers), then one of the 1-3 left.
template <class Group>
inline void InGroupsOfFour(int count, Group group) {
  int first = 0;
  for (; first + 4 <= count; first += 4) group(std::integral_constant<int, 4>{}, first);
  switch (count - first) {
    case 3:
      return group(std::integral_constant<int, 3>{}, first);
    case 2:
      return group(std::integral_constant<int, 2>{}, first);
    case 1:
      return group(std::integral_constant<int, 1>{}, first);
  }
}

template <int L>
struct AddBranchLightTermsRowOf {
  LAYERLAB_AVX2 static void Run(const Rgb4* const* rows, int stride, const Rgb4* w, int terms, int begin, int end,
                                Rgb4* row) {
    InGroupsOfFour(terms, [&](auto g, int q) {
      AddTermsGroup<L, decltype(g)::value>(rows + q * stride, stride, w + q, begin, end, row);
    });
  }
};

template <int L>
struct JointSumsRowOf {
  LAYERLAB_AVX2 static void Run(const Rgb4* const* rows, Rgb4 w, int cols, const float* l, bool exact_last,
                                const Rgb4* light, Rgb4* const* num, Rgb4* const* den) {
    const float* r[L];
    float* n[L];
    float* d[L];
    for (int k = 0; k < L; ++k) {
      r[k] = reinterpret_cast<const float*>(rows[k]);
      n[k] = reinterpret_cast<float*>(num[k]), d[k] = reinterpret_cast<float*>(den[k]);
    }
    const float* li = reinterpret_cast<const float*>(light);
    const __m256 w2 = Twice(w);
    int j = 0;
    for (; j + 3 <= cols; j += 2) {  // rays j, j + 1 read up to ray j + 2's green
      __m256 v[L];
      for (int k = 0; k < L; ++k) v[k] = _mm256_loadu_ps(r[k] + j * 4);
      const __m256 lightj = _mm256_loadu_ps(li + j * 4);
      AddJointSumsOfTwoRays<L>(w2, v, _mm256_sub_ps(lightj, LoadTwoRaysOver(l + j * 3)), lightj, j, n, d);
    }
    const Rgb4* rest[L];
    Rgb4 *rest_num[L], *rest_den[L];
    for (int k = 0; k < L; ++k) rest[k] = rows[k] + j, rest_num[k] = num[k] + j, rest_den[k] = den[k] + j;
    baseline::JointSumsRow({rest, L, w, cols - j}, {l + j * 3, exact_last}, light + j, {rest_num, rest_den});
  }
};

}  // namespace

LAYERLAB_AVX2 void JointSumsRow(BranchRow branch, PackedRow l, const Rgb4* light, MemberRowSums sums) {
  ForLayerCount<JointSumsRowOf>(branch.layers, branch.rows, branch.w, branch.cols, l.values, l.exact_last, light,
                                sums.res, sums.den);
}

LAYERLAB_AVX2 void AddBranchLightRow(BranchRow branch, Rgb4* row) {
  ForLayerCount<AddBranchLightRowOf>(branch.layers, branch.rows, branch.w, branch.cols, row);
}

LAYERLAB_AVX2 void AddBranchLightTermsRow(BranchRows terms, int begin, int end, Rgb4* row) {
  ForLayerCount<AddBranchLightTermsRowOf>(terms.layers, terms.rows, terms.stride, terms.w, terms.branches, begin, end,
                                          row);
}

LAYERLAB_AVX2 void UpdateSumsRow(const float* r, const Rgb4* q, UpdateRowSums sums, int cols) {
  Rgb4 *num = sums.num, *den = sums.den;
  float* n = reinterpret_cast<float*>(num);
  float* d = reinterpret_cast<float*>(den);
  const __m256 ones = _mm256_setr_ps(1, 1, 1, 0, 1, 1, 1, 0);
  int j = 0;
  for (; j + 3 <= cols; j += 2) {  // rays j, j + 1 read up to ray j + 2's green
    const __m256 qj = q ? _mm256_loadu_ps(reinterpret_cast<const float*>(q + j)) : ones;
    _mm256_storeu_ps(n + j * 4,
                     _mm256_add_ps(_mm256_loadu_ps(n + j * 4), _mm256_mul_ps(LoadTwoRaysOver(r + j * 3), qj)));
    _mm256_storeu_ps(d + j * 4, _mm256_add_ps(_mm256_loadu_ps(d + j * 4), _mm256_mul_ps(qj, qj)));
  }
  baseline::UpdateSumsRow(r + j * 3, q ? q + j : nullptr, {num + j, den + j}, cols - j);
}

namespace {

// G rows of UpdateSumsRows, the sums of two rays at a time in registers.
template <int G>
LAYERLAB_AVX2 void UpdateSumsGroup(const float* const* r, const Rgb4* const* q, Rgb4* num, Rgb4* den, int cols) {
  float* n = reinterpret_cast<float*>(num);
  float* d = reinterpret_cast<float*>(den);
  const float* rg[G];
  const float* qg[G];
  for (int g = 0; g < G; ++g) rg[g] = r[g], qg[g] = q ? reinterpret_cast<const float*>(q[g]) : nullptr;
  const __m256 ones = _mm256_setr_ps(1, 1, 1, 0, 1, 1, 1, 0);
  int j = 0;
  for (; j + 3 <= cols; j += 2) {  // rays j, j + 1 read up to ray j + 2's green
    __m256 nj = _mm256_loadu_ps(n + j * 4), dj = _mm256_loadu_ps(d + j * 4);
    for (int g = 0; g < G; ++g) {
      const __m256 qj = q ? _mm256_loadu_ps(qg[g] + j * 4) : ones;
      nj = _mm256_add_ps(nj, _mm256_mul_ps(LoadTwoRaysOver(rg[g] + j * 3), qj));
      dj = _mm256_add_ps(dj, _mm256_mul_ps(qj, qj));
    }
    _mm256_storeu_ps(n + j * 4, nj), _mm256_storeu_ps(d + j * 4, dj);
  }
  for (int g = 0; g < G; ++g)
    baseline::UpdateSumsRow(rg[g] + j * 3, q ? q[g] + j : nullptr, {num + j, den + j}, cols - j);
}

// PairSumsRows' row pairs [0, G) of `pairs` (its count not read): the first sets the sums unless `add`.
template <int G>
LAYERLAB_AVX2 void PairSumsGroup(PairRows pairs, PairColumns columns, bool add, UpdateRowSums sums) {
  const Rgb4* const* cells = pairs.cells;
  const Rgb4* const* q_rows = pairs.q_rows;
  const float* rays = pairs.rays;
  const int32_t* q_col = columns.q_col;
  const int width = columns.width;
  Rgb4 *sum_rq = sums.num, *sum_qq = sums.den;
  __m256 r8[G];
  for (int g = 0; g < G; ++g) r8[g] = _mm256_set1_ps(rays[g]);
  int j = 0;
  for (; j + 2 <= width; j += 2) {
    const int32_t c0 = q_col[j], c1 = q_col[j + 1];
    float* rq = reinterpret_cast<float*>(sum_rq + j);
    float* qq = reinterpret_cast<float*>(sum_qq + j);
    __m256 rqj = _mm256_setzero_ps(), qqj = _mm256_setzero_ps();
    for (int g = 0; g < G; ++g) {
      const __m256 q = _mm256_set_m128(__m128(q_rows[g][c1]), __m128(q_rows[g][c0]));
      const __m256 c = _mm256_loadu_ps(reinterpret_cast<const float*>(cells[g] + j));
      const __m256 cq = _mm256_mul_ps(c, q), rqq = _mm256_mul_ps(r8[g], _mm256_mul_ps(q, q));
      if (g > 0) {
        rqj = _mm256_add_ps(rqj, cq), qqj = _mm256_add_ps(qqj, rqq);
      } else if (add) {
        rqj = _mm256_add_ps(_mm256_loadu_ps(rq), cq), qqj = _mm256_add_ps(_mm256_loadu_ps(qq), rqq);
      } else {
        rqj = cq, qqj = rqq;
      }
    }
    _mm256_storeu_ps(rq, rqj), _mm256_storeu_ps(qq, qqj);
  }
  for (int g = 0; g < G && j < width; ++g)
    baseline::PairSumsRow(cells[g] + j, q_rows[g], rays[g], {q_col + j, width - j}, add || g > 0,
                          {sum_rq + j, sum_qq + j});
}

}  // namespace

LAYERLAB_AVX2 void PairSumsRows(PairRows pairs, PairColumns columns, UpdateRowSums sums) {
  InGroupsOfFour(pairs.pairs, [&](auto g, int first) {
    const PairRows group{pairs.cells + first, pairs.q_rows + first, pairs.rays + first, decltype(g)::value};
    PairSumsGroup<decltype(g)::value>(group, columns, first > 0, sums);
  });
}

LAYERLAB_AVX2 void PairSumsRow(const Rgb4* cells, const Rgb4* q_row, float rays, PairColumns columns, bool add,
                               UpdateRowSums sums) {
  const int32_t* q_col = columns.q_col;
  const int width = columns.width;
  Rgb4 *sum_rq = sums.num, *sum_qq = sums.den;
  const __m256 r8 = _mm256_set1_ps(rays);
  int j = 0;
  for (; j + 2 <= width; j += 2) {
    const __m256 q = _mm256_set_m128(__m128(q_row[q_col[j + 1]]), __m128(q_row[q_col[j]]));
    float* rq = reinterpret_cast<float*>(sum_rq + j);
    float* qq = reinterpret_cast<float*>(sum_qq + j);
    const __m256 c = _mm256_loadu_ps(reinterpret_cast<const float*>(cells + j));
    const __m256 cq = _mm256_mul_ps(c, q), rqq = _mm256_mul_ps(r8, _mm256_mul_ps(q, q));
    _mm256_storeu_ps(rq, add ? _mm256_add_ps(_mm256_loadu_ps(rq), cq) : cq);
    _mm256_storeu_ps(qq, add ? _mm256_add_ps(_mm256_loadu_ps(qq), rqq) : rqq);
  }
  if (j < width) baseline::PairSumsRow(cells + j, q_row, rays, {q_col + j, width - j}, add, {sum_rq + j, sum_qq + j});
}

LAYERLAB_AVX2 void UpdateSumsRows(const float* const* r, const Rgb4* const* q, int rows, UpdateRowSums sums, int cols) {
  InGroupsOfFour(rows, [&](auto g, int first) {
    UpdateSumsGroup<decltype(g)::value>(r + first, q ? q + first : nullptr, sums.num, sums.den, cols);
  });
}

LAYERLAB_AVX2 double UpdateSumsAndErrorRow(const float* r, const Rgb4* q, const Rgb4* own, Rgb4 w, UpdateRowSums sums,
                                           int cols) {
  Rgb4 *num = sums.num, *den = sums.den;
  float* n = reinterpret_cast<float*>(num);
  float* d = reinterpret_cast<float*>(den);
  const float* o = reinterpret_cast<const float*>(own);
  const __m256 ones = _mm256_setr_ps(1, 1, 1, 0, 1, 1, 1, 0), w2 = Twice(w);
  __m256d even = _mm256_setzero_pd(), odd = _mm256_setzero_pd();
  int j = 0;
  for (; j + 3 <= cols; j += 2) {  // j even; rays j, j + 1 read up to ray j + 2's green
    const __m256 qj = q ? _mm256_loadu_ps(reinterpret_cast<const float*>(q + j)) : ones;
    const __m256 rj = LoadTwoRaysOver(r + j * 3);
    _mm256_storeu_ps(n + j * 4, _mm256_add_ps(_mm256_loadu_ps(n + j * 4), _mm256_mul_ps(rj, qj)));
    _mm256_storeu_ps(d + j * 4, _mm256_add_ps(_mm256_loadu_ps(d + j * 4), _mm256_mul_ps(qj, qj)));
    const __m256 light = _mm256_mul_ps(_mm256_mul_ps(w2, _mm256_loadu_ps(o + j * 4)), qj);
    even = _mm256_add_pd(even, Squared(Rgb4(_mm256_castps256_ps128(rj)), Rgb4(_mm256_castps256_ps128(light))));
    odd = _mm256_add_pd(odd, Squared(Rgb4(_mm256_extractf128_ps(rj, 1)), Rgb4(_mm256_extractf128_ps(light, 1))));
  }
  for (; j < cols; ++j) {
    const Rgb4 qj = q ? q[j] : Rgb4{1, 1, 1, 0};
    const Rgb4 rj = j + 1 < cols ? LoadRgbOver(r + j * 3) : LoadRgb(r + j * 3);
    num[j] += rj * qj;
    den[j] += qj * qj;
    __m256d& sum = j % 2 == 0 ? even : odd;
    sum = _mm256_add_pd(sum, Squared(rj, w * own[j] * qj));
  }
  alignas(32) double e[4], od[4];
  _mm256_store_pd(e, even), _mm256_store_pd(od, odd);
  return (e[0] + od[0]) + (e[1] + od[1]) + (e[2] + od[2]);
}

LAYERLAB_AVX2 double SquaredErrorRow(const float* target, const Rgb4* light, int cols, bool exact_last) {
  __m256d even = _mm256_setzero_pd(), odd = _mm256_setzero_pd();
  const int safe = exact_last ? cols - 1 : cols;
  int j = 0;
  for (; j + 1 < safe; j += 2) {
    even = _mm256_add_pd(even, Squared(LoadRgbOver(target + j * 3), light[j]));
    odd = _mm256_add_pd(odd, Squared(LoadRgbOver(target + j * 3 + 3), light[j + 1]));
  }
  for (; j < cols; ++j)
    even = _mm256_add_pd(even, Squared(j < safe ? LoadRgbOver(target + j * 3) : LoadRgb(target + j * 3), light[j]));
  alignas(32) double e[4], o[4];
  _mm256_store_pd(e, even), _mm256_store_pd(o, odd);
  return (e[0] + o[0]) + (e[1] + o[1]) + (e[2] + o[2]);
}

LAYERLAB_AVX2 void RemainderRow(const float* target, const Rgb4* light, int cols, float* out) {
  const float* l = reinterpret_cast<const float*>(light);
  const __m256 zero = _mm256_setzero_ps();
  int j = 0;
  // max(0, d), in this order, is std::max(d, 0.0f) for every d, -0 included.
  for (; j + 3 <= cols; j += 2)
    StoreTwoRaysOver(_mm256_max_ps(zero, _mm256_sub_ps(LoadTwoRaysOver(target + j * 3), _mm256_loadu_ps(l + j * 4))),
                     out + j * 3);
  baseline::RemainderRow(target + j * 3, light + j, cols - j, out + j * 3);
}

LAYERLAB_AVX2 void PackRow(const Rgb4* row, int cols, float* out) {
  const float* in = reinterpret_cast<const float*>(row);
  int j = 0;
  for (; j + 3 <= cols; j += 2) StoreTwoRaysOver(_mm256_loadu_ps(in + j * 4), out + j * 3);
  baseline::PackRow(row + j, cols - j, out + j * 3);
}

}  // namespace layerlab::avx2

#endif  // LAYERLAB_ROW_KERNELS_AVX2
