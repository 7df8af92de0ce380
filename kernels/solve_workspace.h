// The working memory of the passes over the rays (synthesis, the
// multiplicative update's sums, the joint pass), in one place: a part per
// thread of the team, laid out by the thread count, and the parts the team
// shares. The solve loop (solvers/solve_loop.h) makes one for the model, the
// solver's passes and the thread count before the first pass, and it is
// released when the solve ends; nothing of it is a thread_local.
//
// Every buffer is sized once, here, by SizeWorkspace: the same function gives
// the layout without allocating (SolveWorkspace::Layout), which is what the
// memory estimate counts (solvers/memory_estimate.h), so the two cannot
// disagree. The passes only resize buffers to the sizes given here (no
// reallocation); Bytes() gives what is held, for the test that they did not grow.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "layerlab/framework/rgb4.h"
#include "layerlab/kernels/one_tap_view.h"
#include "layerlab/kernels/pair_lattice.h"
#include "layerlab/kernels/workspace_pass.h"
#include "layerlab/systems/display_model.h"

namespace layerlab {

// One part of the layout: `bytes` for each thread, or once for a shared part.
struct WorkspacePart {
  std::string name;
  size_t bytes = 0;
  bool per_thread = false;
};

struct WorkspaceLayout {
  int threads = 1;
  std::vector<WorkspacePart> parts;
  size_t bytes() const;
  // "per thread 16.3 MB x 2 (column caches 5.1 MB, ...) + shared 9.0 MB (...)"
  std::string Describe() const;
};

// Sizes buffers and records them in a layout: one function for both, so that
// an estimate is what is allocated (SolveWorkspace, retina/retina_workspace.h).
struct WorkspaceSizer {
  bool allocate;
  WorkspaceLayout* layout;

  // Adds `bytes` to the part of that name and kind (none for 0).
  void Record(const std::string& name, size_t bytes, bool per_thread);
  // A buffer of n elements; a thread's part is recorded once (for thread 0)
  // and allocated for each.
  template <class T, class A>
  void Buffer(const std::string& name, std::vector<T, A>* v, size_t n, bool per_thread, bool record) {
    if (record) Record(name, n * sizeof(T), per_thread);
    if (allocate) v->assign(n, T{});
  }
};

// A ray row of a multiplicative update's pass waiting to be summed into
// row `layer_row` of the layer being updated (kernels/one_tap_update.cpp).
struct PendingSumRow {
  int layer_row;
  const float* target;  // the ray row's target, packed
  const Rgb4* product;  // the other layer at its rays, or nullptr for 1
};

// One thread's buffers. The ones of view size ([ray][rgb]) are named for their use.
struct ThreadWorkspace {
  // ViewSynthesizer: its one-tap layers resampled to the rays' columns of the
  // last view column this thread synthesized, [layer][its row][ray column].
  uint64_t cache_owner = 0;
  int cache_vc = -1;
  std::vector<std::vector<Rgb4>> cache;
  std::vector<Rgb4> row, rest_row;  // ray rows of light
  std::vector<float> synthesized;   // a view of light (general branches, squared error)
  std::vector<float> branch;        // a view of one branch's light (general branches, the hybrid's chase)
  std::vector<float> gathered;      // a view of one layer's samples (projection.h: GatherMultiply of several taps)

  // The sums' passes: layers resampled to the rays' columns of one view run, [layer][its row][ray column].
  std::vector<std::vector<Rgb4>> resampled;
  ColumnSums update_sums;                   // the layer being updated (one-tap path)
  std::vector<ColumnSums> layer_sums;       // [layer] (the joint pass, one-tap path)
  std::vector<Rgb4> product, zeros, light;  // ray rows
  std::vector<float> target;                // a view of what a branch should emit, when it is computed
  std::vector<PendingSumRow> pending_rows;  // a view run's rows, summed grouped by layer row
  // The general path: per-layer float sums, [layer][pixel * 3 + c] (num: the
  // multiplicative update's numerator, or the joint pass's residual), and view buffers.
  std::vector<std::vector<float>> num, den;
  std::vector<float> rest, sampled, samples, residual_terms, denominator_terms;
};

class SolveWorkspace {
 public:
  // Allocates (and touches) every part of the layout.
  SolveWorkspace(const DisplayModel& model, int threads, unsigned passes);
  // The layout the constructor allocates, without allocating.
  static WorkspaceLayout Layout(const DisplayModel& model, int threads, unsigned passes);

  int threads() const { return static_cast<int>(threads_.size()); }
  // The calling thread's part (omp_get_thread_num(); thread 0 outside a parallel region).
  ThreadWorkspace& thread();
  ThreadWorkspace& thread(int me) { return threads_[me]; }

  // Shared: the patterns padded to [pixel][rgb, 0] (filled by each pass from the patterns it reads).
  PaddedLayers padded;
  // Shared: per-view errors of a pass (summed in view order by its caller).
  std::vector<double> view_errors;
  // Shared: merged multiplicative-update sums, [pixel * 3 + c] of the layer updated.
  std::vector<double> update_num, update_den;
  // Shared: one update's sums kept for the next iteration (multiplicative, hybrid).
  std::vector<double> kept_num, kept_den;
  // Shared: the joint pass's merged sums, [layer][pixel * 3 + c].
  std::vector<std::vector<double>> joint_residual, joint_den;  // JointPass::residual(), denominator()
  // Shared: a branch's target binned by pixel pair (PairLattice::Bin), room for the largest branch where it pays.
  PairCells pair_cells;
  // Shared: the same behind real lenses (MappedPairs::Bin), and its per-thread sums.
  std::vector<float> pair_sums;
  std::vector<std::vector<float>> pair_parts;

  // What the buffers hold now (capacities): the layout's bytes unless a pass grew one.
  size_t Bytes() const;

 private:
  SolveWorkspace() = default;
  friend struct SolveWorkspaceSizer;
  std::vector<ThreadWorkspace> threads_;
};

}  // namespace layerlab
