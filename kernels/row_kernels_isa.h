// The two builds behind row_kernels.h, for its dispatch only.
#pragma once

#include <cstdint>

#include "layerlab/framework/rgb4.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define LAYERLAB_ROW_KERNELS_AVX2 1
#else
#define LAYERLAB_ROW_KERNELS_AVX2 0
#endif

namespace layerlab {

// The kernels of row_kernels.h, once for each build.
#define LAYERLAB_ROW_KERNEL_SIGNATURES                                                                              \
  void AddBranchLightRow(const Rgb4* const* rows, int layers, Rgb4 w, int cols, Rgb4* row);                         \
  void AddBranchLightTermsRow(const Rgb4* const* rows, int stride, int layers, const Rgb4* w, int terms, int begin, \
                              int end, Rgb4* row);                                                                  \
  void UpdateSumsRow(const float* r, const Rgb4* q, Rgb4* num, Rgb4* den, int cols);                                \
  void PairSumsRow(const Rgb4* cells, const Rgb4* q_row, const int32_t* q_col, float rays, int width, bool add,     \
                   Rgb4* sum_rq, Rgb4* sum_qq);                                                                     \
  void PairSumsRows(const Rgb4* const* cells, const Rgb4* const* q_rows, const float* rays, int pairs,              \
                    const int32_t* q_col, int width, Rgb4* sum_rq, Rgb4* sum_qq);                                   \
  void UpdateSumsRows(const float* const* r, const Rgb4* const* q, int rows, Rgb4* num, Rgb4* den, int cols);       \
  double UpdateSumsAndErrorRow(const float* r, const Rgb4* q, const Rgb4* own, Rgb4 w, Rgb4* num, Rgb4* den,        \
                               int cols);                                                                           \
  double SquaredErrorRow(const float* target, const Rgb4* light, int cols, bool exact_last);                        \
  void RemainderRow(const float* target, const Rgb4* light, int cols, float* out);                                  \
  void PackRow(const Rgb4* row, int cols, float* out);                                                              \
  void JointSumsRow(const Rgb4* const* rows, int layers, Rgb4 w, int cols, const float* l, bool exact_last,         \
                    const Rgb4* light, Rgb4* const* num, Rgb4* const* den);

namespace baseline {
LAYERLAB_ROW_KERNEL_SIGNATURES
}  // namespace baseline

#if LAYERLAB_ROW_KERNELS_AVX2
// Call only where CpuHasAvx2().
namespace avx2 {
LAYERLAB_ROW_KERNEL_SIGNATURES
}  // namespace avx2
#endif

#undef LAYERLAB_ROW_KERNEL_SIGNATURES

}  // namespace layerlab
