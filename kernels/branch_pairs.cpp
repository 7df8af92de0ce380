#include "layerlab/kernels/branch_pairs.h"

namespace layerlab {

std::optional<BranchPairs> BranchPairs::IfItPays(const DisplayModel& model, size_t branch) {
  BranchPairs pairs;
  pairs.list_ = model.pair_list(branch);
  if (!pairs.list_) pairs.lattice_ = PairLattice::IfItPays(model, branch);
  if (!pairs.list_ && !pairs.lattice_) return std::nullopt;
  return pairs;
}

void BranchPairs::Bin(const LightField& r, SolveWorkspace* workspace) const {
  if (lattice_)
    lattice_->Bin(r, &workspace->pair_cells);
  else
    list_->Bin(r, &workspace->pair_sums, &workspace->pair_parts);
}

void BranchPairs::ComputeUpdate(const DisplayModel& model, size_t branch, int layer, const Patterns& t,
                                SolveWorkspace* workspace, LayerUpdate* update) const {
  if (lattice_)
    ComputeLayerUpdateFromPairs(model, {branch, layer}, *lattice_, workspace->pair_cells, t, workspace, update);
  else
    ComputeLayerUpdateFromMappedPairs(model, {branch, layer}, *list_, workspace->pair_sums, t, update);
}

}  // namespace layerlab
