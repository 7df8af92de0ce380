// The per-ray-row kernels of the one-tap passes (synthesis, multiplicative
// update, objective, chase remainders): one ray row at a time, rays as
// [ray][rgb, 0] (Rgb4) or packed [ray][rgb]. Two builds of each: the
// baseline (SSE2, one ray per instruction) and, on CPUs that have it, AVX2
// (two rays per instruction). Both do the same operations in the same order
// on every lane, so their results are bit for bit the same; tests check it.
#pragma once

#include "layerlab/framework/rgb4.h"
#include "layerlab/kernels/row_args.h"

namespace layerlab {

// row[j] += w prod_k rows[k][j] over the branch row's layers and rays.
void AddBranchLightRow(BranchRow branch, Rgb4* row);

// row[j] += w[q] prod_k rows[q stride + k][j] for each term q < terms.branches
// in turn, j in [begin, end): the sums AddBranchLightRow makes term by term,
// in the same order, with each pixel's running sum kept in a register over a
// few terms (the retinal image adds a hundred terms per row).
void AddBranchLightTermsRow(BranchRows terms, int begin, int end, Rgb4* row);

// The multiplicative update's column sums over one ray row:
// num[j] += r_j q[j], den[j] += q[j]^2; r packed [ray][rgb], q = nullptr means 1.
void UpdateSumsRow(const float* r, const Rgb4* q, UpdateRowSums sums, int cols);

// One row pair of a pixel-pair lattice (pair_lattice.h) into a layer row's
// sums per column pair: num[j] += cells[j] q_j, den[j] += rays q_j^2,
// q_j = q_row[q_col[j]] (the other layer's pixel of column pair j); without
// `add` the sums are set to those terms instead.
void PairSumsRow(const Rgb4* cells, const Rgb4* q_row, float rays, PairColumns columns, bool add, UpdateRowSums sums);

// PairSumsRow for the row pairs of one layer row in turn, the first setting
// the sums and the others adding: the same adds in the same order, each
// column pair's two sums kept in registers over a few row pairs.
// pairs.pairs >= 1 (with none the sums are left as they were, not zeroed).
void PairSumsRows(PairRows pairs, PairColumns columns, UpdateRowSums sums);

// UpdateSumsRow for `rows` ray rows that sum into the same num and den, in
// turn: the same adds in the same order, each ray column's two sums kept in
// registers over a few rows. q == nullptr means 1 for every row; else q[g]
// is row g's.
void UpdateSumsRows(const float* const* r, const Rgb4* const* q, int rows, UpdateRowSums sums, int cols);

// UpdateSumsRow, and in the same pass the squared error of the branch's
// light w own[j] q[j] against r over the row (in double, as SquaredErrorRow
// sums it), `own` being the updated layer's values at the rays.
double UpdateSumsAndErrorRow(const float* r, const Rgb4* q, const Rgb4* own, Rgb4 w, UpdateRowSums sums, int cols);

// The joint pass's sums for every layer a of one branch row (1 to 4 layers),
// q_a = w prod_{k != a} rows[k][j]:
// res[a][j] += (light[j] - l_j) q_a, den[a][j] += light[j] q_a. The residual
// is summed itself, not as den minus a sum of l_j q_a: near a solution the
// two agree to many digits, and their float difference would be mostly
// rounding.
void JointSumsRow(BranchRow branch, PackedRow l, const Rgb4* light, MemberRowSums sums);

// Sum over the row of (target - light)^2, channels 0-2, in double; `target`
// packed. All rays but the last read one float past their own unless
// `exact_last` is false (then the last does too).
double SquaredErrorRow(const float* target, const Rgb4* light, int cols, bool exact_last);

// out = max(0, target - light), target and out packed; writes exactly cols x 3 floats.
void RemainderRow(const float* target, const Rgb4* light, int cols, float* out);

// out = row packed; writes exactly cols x 3 floats, so that rows may be
// written by different threads in any order.
void PackRow(const Rgb4* row, int cols, float* out);

enum class RowKernelIsa { kBaseline, kAvx2 };
// The build the kernels use: AVX2 where the CPU has it, unless forced here
// or by LAYERLAB_ROW_KERNELS=baseline in the environment.
RowKernelIsa ActiveRowKernels();
// For tests and benchmarks: use `isa` from now on (kAvx2 only where the CPU has it; false otherwise).
bool ForceRowKernels(RowKernelIsa isa);
bool CpuHasAvx2();

}  // namespace layerlab
