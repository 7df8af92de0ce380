// The two builds behind row_kernels.h, for its dispatch only.
#pragma once

#include "layerlab/framework/rgb4.h"
#include "layerlab/kernels/row_args.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define LAYERLAB_ROW_KERNELS_AVX2 1
#else
#define LAYERLAB_ROW_KERNELS_AVX2 0
#endif

namespace layerlab {

// The kernels of row_kernels.h, once for each build.
#define LAYERLAB_ROW_KERNEL_SIGNATURES                                                                                \
  void AddBranchLightRow(BranchRow branch, Rgb4* row);                                                                \
  void AddBranchLightTermsRow(BranchRows terms, int begin, int end, Rgb4* row);                                       \
  void UpdateSumsRow(const float* r, const Rgb4* q, UpdateRowSums sums, int cols);                                    \
  void PairSumsRow(const Rgb4* cells, const Rgb4* q_row, float rays, PairColumns columns, bool add,                   \
                   UpdateRowSums sums);                                                                               \
  void PairSumsRows(PairRows pairs, PairColumns columns, UpdateRowSums sums);                                         \
  void UpdateSumsRows(const float* const* r, const Rgb4* const* q, int rows, UpdateRowSums sums, int cols);           \
  double UpdateSumsAndErrorRow(const float* r, const Rgb4* q, const Rgb4* own, Rgb4 w, UpdateRowSums sums, int cols); \
  double SquaredErrorRow(const float* target, const Rgb4* light, int cols, bool exact_last);                          \
  void RemainderRow(const float* target, const Rgb4* light, int cols, float* out);                                    \
  void PackRow(const Rgb4* row, int cols, float* out);                                                                \
  void JointSumsRow(BranchRow branch, PackedRow l, const Rgb4* light, MemberRowSums sums);

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
