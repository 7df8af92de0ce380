#include "layerlab/kernels/row_kernels.h"

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <cstring>
#include <string>
#if defined(__SSE2__)
#include <immintrin.h>
#endif

#include "layerlab/framework/error.h"
#include "layerlab/kernels/joint_sums_ray.h"
#include "layerlab/kernels/row_kernels_isa.h"
#include "layerlab/kernels/unrolled_layers.h"

namespace layerlab {
namespace baseline {
namespace {

template <int L>
struct AddBranchLightRowOf {
  static void Run(const Rgb4* const* rows, Rgb4 w, int cols, Rgb4* row) {
    const Rgb4* r[L];
    for (int k = 0; k < L; ++k) r[k] = rows[k];
    for (int j = 0; j < cols; ++j) {
      Rgb4 p = w;
      for (int k = 0; k < L; ++k) p *= r[k][j];
      row[j] += p;
    }
  }
};

}  // namespace

void AddBranchLightRow(BranchRow branch, Rgb4* row) {
  ForLayerCount<AddBranchLightRowOf>(branch.layers, branch.rows, branch.w, branch.cols, row);
}

void AddBranchLightTermsRow(BranchRows terms, int begin, int end, Rgb4* row) {
  for (int q = 0; q < terms.branches; ++q) {
    const Rgb4* at[kMaxOneTapLayers];
    for (int k = 0; k < terms.layers; ++k) at[k] = terms.rows[q * terms.stride + k] + begin;
    baseline::AddBranchLightRow({at, terms.layers, terms.w[q], end - begin}, row + begin);
  }
}

void UpdateSumsRow(const float* r, const Rgb4* q, UpdateRowSums sums, int cols) {
  Rgb4 *num = sums.num, *den = sums.den;
  int j = 0;
  for (; j + 1 < cols; ++j) {  // all but the last ray read one float past their own
    const Rgb4 qj = q ? q[j] : Rgb4{1, 1, 1, 0};
    num[j] += LoadRgbOver(r + j * 3) * qj;
    den[j] += qj * qj;
  }
  for (; j < cols; ++j) {
    const Rgb4 qj = q ? q[j] : Rgb4{1, 1, 1, 0};
    num[j] += LoadRgb(r + j * 3) * qj;
    den[j] += qj * qj;
  }
}

void PairSumsRow(const Rgb4* cells, const Rgb4* q_row, float rays, PairColumns columns, bool add, UpdateRowSums sums) {
  const int32_t* q_col = columns.q_col;
  Rgb4 *sum_rq = sums.num, *sum_qq = sums.den;
  for (int j = 0; j < columns.width; ++j) {
    const Rgb4 q = q_row[q_col[j]];
    const Rgb4 rq = cells[j] * q, qq = rays * (q * q);
    sum_rq[j] = add ? sum_rq[j] + rq : rq;
    sum_qq[j] = add ? sum_qq[j] + qq : qq;
  }
}

void PairSumsRows(PairRows pairs, PairColumns columns, UpdateRowSums sums) {
  for (int k = 0; k < pairs.pairs; ++k)
    baseline::PairSumsRow(pairs.cells[k], pairs.q_rows[k], pairs.rays[k], columns, k > 0, sums);
}

void UpdateSumsRows(const float* const* r, const Rgb4* const* q, int rows, UpdateRowSums sums, int cols) {
  for (int g = 0; g < rows; ++g) baseline::UpdateSumsRow(r[g], q ? q[g] : nullptr, sums, cols);
}

// The squared errors are summed in two-double vectors, one SSE register each
// (a four-double vector without AVX is emulated through the stack, and each
// ray's add then waits on a store), even and odd rays on separate sums so
// that no add waits for the last.
namespace {

using Double2 = double __attribute__((vector_size(16)));

// Channels 0-1 and 2-3 of a ray, in double; lane 3 is padding, never read.
#if defined(__SSE2__)
// GCC 12 turns the generic form below into scalar conversions.
inline Double2 Low(Rgb4 v) { return Double2(_mm_cvtps_pd(__m128(v))); }
inline Double2 High(Rgb4 v) { return Double2(_mm_cvtps_pd(_mm_movehl_ps(__m128(v), __m128(v)))); }
#else
inline Double2 Low(Rgb4 v) { return __builtin_convertvector(__builtin_shufflevector(v, v, 0, 1), Double2); }
inline Double2 High(Rgb4 v) { return __builtin_convertvector(__builtin_shufflevector(v, v, 2, 3), Double2); }
#endif

// rg += (t - l)^2 in channels 0-1, b in 2 (and the padding).
inline void AddSquared(Rgb4 t, Rgb4 l, Double2& rg, Double2& b) {
  const Double2 d_rg = Low(t) - Low(l), d_b = High(t) - High(l);
  rg += d_rg * d_rg, b += d_b * d_b;
}

}  // namespace

double UpdateSumsAndErrorRow(const float* r, const Rgb4* q, const Rgb4* own, Rgb4 w, UpdateRowSums sums, int cols) {
  Rgb4 *num = sums.num, *den = sums.den;
  Double2 rg0 = {}, b0 = {}, rg1 = {}, b1 = {};  // even rays, odd rays
  auto ray = [&](int j, Rgb4 rj, Double2& rg, Double2& b) {
    const Rgb4 qj = q ? q[j] : Rgb4{1, 1, 1, 0};
    num[j] += rj * qj;
    den[j] += qj * qj;
    AddSquared(rj, w * own[j] * qj, rg, b);
  };
  int j = 0;
  for (; j + 2 < cols; j += 2) {  // neither is the last ray: both may read one float past their own
    ray(j, LoadRgbOver(r + j * 3), rg0, b0);
    ray(j + 1, LoadRgbOver(r + j * 3 + 3), rg1, b1);
  }
  for (; j < cols; ++j) {
    const Rgb4 rj = j + 1 < cols ? LoadRgbOver(r + j * 3) : LoadRgb(r + j * 3);
    if (j % 2 == 0)
      ray(j, rj, rg0, b0);
    else
      ray(j, rj, rg1, b1);
  }
  return (rg0[0] + rg1[0]) + (rg0[1] + rg1[1]) + (b0[0] + b1[0]);
}

double SquaredErrorRow(const float* target, const Rgb4* light, int cols, bool exact_last) {
  Double2 rg0 = {}, b0 = {}, rg1 = {}, b1 = {};
  const int safe = exact_last ? cols - 1 : cols;
  int j = 0;
  for (; j + 1 < safe; j += 2) {
    AddSquared(LoadRgbOver(target + j * 3), light[j], rg0, b0);
    AddSquared(LoadRgbOver(target + j * 3 + 3), light[j + 1], rg1, b1);
  }
  for (; j < cols; ++j) AddSquared(j < safe ? LoadRgbOver(target + j * 3) : LoadRgb(target + j * 3), light[j], rg0, b0);
  return (rg0[0] + rg1[0]) + (rg0[1] + rg1[1]) + (b0[0] + b1[0]);
}

void RemainderRow(const float* target, const Rgb4* light, int cols, float* out) {
  for (int j = 0; j < cols; ++j) {
    const Rgb4 d = LoadRgb(target + j * 3) - light[j];
    for (int c = 0; c < 3; ++c) out[j * 3 + c] = std::max(d[c], 0.0f);
  }
}

void PackRow(const Rgb4* row, int cols, float* out) {
  if (cols <= 0) return;
  // Each 16-byte store spills its padding onto the next ray's red, which the
  // next store overwrites; the last ray is stored exactly.
  for (int j = 0; j + 1 < cols; ++j) std::memcpy(out + j * 3, &row[j], sizeof(Rgb4));
  StoreRgb(row[cols - 1], out + (cols - 1) * 3);
}

namespace {

template <int L>
struct JointSumsRowOf {
  static void Run(const Rgb4* const* rows, Rgb4 w, int cols, const float* l, bool exact_last, const Rgb4* light,
                  Rgb4* const* num, Rgb4* const* den) {
    const Rgb4* r[L];
    Rgb4* n[L];
    Rgb4* d[L];
    for (int k = 0; k < L; ++k) r[k] = rows[k], n[k] = num[k], d[k] = den[k];
    const int safe = exact_last ? cols - 1 : cols;
    for (int j = 0; j < cols; ++j) {
      Rgb4 v[L];
      for (int k = 0; k < L; ++k) v[k] = r[k][j];
      const Rgb4 lj = j < safe ? LoadRgbOver(l + j * 3) : LoadRgb(l + j * 3);
      AddJointSumsOfRay<L>(v, w, light[j] - lj, light[j], j, n, d);
    }
  }
};

}  // namespace

void JointSumsRow(BranchRow branch, PackedRow l, const Rgb4* light, MemberRowSums sums) {
  ForLayerCount<JointSumsRowOf>(branch.layers, branch.rows, branch.w, branch.cols, l.values, l.exact_last, light,
                                sums.res, sums.den);
}

}  // namespace baseline

namespace {

// LAYERLAB_ROW_KERNELS=baseline|avx2 picks the build (for measurements); unset: the best the CPU has.
RowKernelIsa FromEnvironment() {
  const char* v = std::getenv("LAYERLAB_ROW_KERNELS");
  if (v == nullptr || std::strcmp(v, "avx2") == 0) return RowKernelIsa::kAvx2;
  if (std::strcmp(v, "baseline") == 0) return RowKernelIsa::kBaseline;
  throw Error(std::string("LAYERLAB_ROW_KERNELS=") + v + ": expected baseline or avx2");
}

std::atomic<RowKernelIsa>& Wanted() {
  static std::atomic<RowKernelIsa> wanted{FromEnvironment()};
  return wanted;
}

bool UseAvx2() {
#if LAYERLAB_ROW_KERNELS_AVX2
  return Wanted().load(std::memory_order_relaxed) == RowKernelIsa::kAvx2 && CpuHasAvx2();
#else
  return false;
#endif
}
}  // namespace

bool CpuHasAvx2() {
#if LAYERLAB_ROW_KERNELS_AVX2
  static const bool has = __builtin_cpu_supports("avx2");
  return has;
#else
  return false;
#endif
}

RowKernelIsa ActiveRowKernels() { return UseAvx2() ? RowKernelIsa::kAvx2 : RowKernelIsa::kBaseline; }

bool ForceRowKernels(RowKernelIsa isa) {
  if (isa == RowKernelIsa::kAvx2 && !CpuHasAvx2()) return false;
  Wanted().store(isa, std::memory_order_relaxed);
  return true;
}

#if LAYERLAB_ROW_KERNELS_AVX2
#define LAYERLAB_DISPATCH(call) return UseAvx2() ? avx2::call : baseline::call
#else
#define LAYERLAB_DISPATCH(call) return baseline::call
#endif

void AddBranchLightRow(BranchRow branch, Rgb4* row) { LAYERLAB_DISPATCH(AddBranchLightRow(branch, row)); }
void AddBranchLightTermsRow(BranchRows terms, int begin, int end, Rgb4* row) {
  LAYERLAB_DISPATCH(AddBranchLightTermsRow(terms, begin, end, row));
}
void UpdateSumsRow(const float* r, const Rgb4* q, UpdateRowSums sums, int cols) {
  LAYERLAB_DISPATCH(UpdateSumsRow(r, q, sums, cols));
}
void PairSumsRow(const Rgb4* cells, const Rgb4* q_row, float rays, PairColumns columns, bool add, UpdateRowSums sums) {
  LAYERLAB_DISPATCH(PairSumsRow(cells, q_row, rays, columns, add, sums));
}
void PairSumsRows(PairRows pairs, PairColumns columns, UpdateRowSums sums) {
  LAYERLAB_DISPATCH(PairSumsRows(pairs, columns, sums));
}
void UpdateSumsRows(const float* const* r, const Rgb4* const* q, int rows, UpdateRowSums sums, int cols) {
  LAYERLAB_DISPATCH(UpdateSumsRows(r, q, rows, sums, cols));
}
double UpdateSumsAndErrorRow(const float* r, const Rgb4* q, const Rgb4* own, Rgb4 w, UpdateRowSums sums, int cols) {
  LAYERLAB_DISPATCH(UpdateSumsAndErrorRow(r, q, own, w, sums, cols));
}
double SquaredErrorRow(const float* target, const Rgb4* light, int cols, bool exact_last) {
  LAYERLAB_DISPATCH(SquaredErrorRow(target, light, cols, exact_last));
}
void RemainderRow(const float* target, const Rgb4* light, int cols, float* out) {
  LAYERLAB_DISPATCH(RemainderRow(target, light, cols, out));
}
void PackRow(const Rgb4* row, int cols, float* out) { LAYERLAB_DISPATCH(PackRow(row, cols, out)); }
void JointSumsRow(BranchRow branch, PackedRow l, const Rgb4* light, MemberRowSums sums) {
  LAYERLAB_DISPATCH(JointSumsRow(branch, l, light, sums));
}

#undef LAYERLAB_DISPATCH

}  // namespace layerlab
