// A two-layer branch's rays binned by the pixel pair they read, so that
// several updates toward the same r sum pairs instead of rays: on the
// lattice where both layers are affine (pair_lattice.h), as a list where a
// real lens bends either (mapped_pairs.h).
#pragma once

#include <optional>

#include "layerlab/kernels/layer_update_sums.h"
#include "layerlab/kernels/pair_lattice.h"
#include "layerlab/systems/mapped_pairs.h"

namespace layerlab {

class BranchPairs {
 public:
  // The binning of branch `branch` where it pays, or none.
  static std::optional<BranchPairs> IfItPays(const DisplayModel& model, size_t branch);

  // r binned into `workspace` (pair_cells for the lattice, pair_sums and pair_parts for the list).
  void Bin(const LightField& r, SolveWorkspace* workspace) const;
  // One update's sums of `layer` (one of the two) from what Bin left in `workspace`.
  void ComputeUpdate(const DisplayModel& model, size_t branch, int layer, const Patterns& t, SolveWorkspace* workspace,
                     LayerUpdate* update) const;

 private:
  std::optional<PairLattice> lattice_;
  const MappedPairs* list_ = nullptr;  // the model's (DisplayModel::pair_list)
};

}  // namespace layerlab
