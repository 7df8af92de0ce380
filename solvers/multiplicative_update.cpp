#include "layerlab/solvers/multiplicative_update.h"

#include <vector>

namespace layerlab {

namespace {
template <class Ratio>
void StepByRatio(const double* den, const SolverOptions& options, std::vector<float>* pattern, Ratio ratio) {
  const float floor = static_cast<float>(options.floor);
#pragma omp parallel for schedule(static)
  for (size_t k = 0; k < pattern->size(); ++k) {
    if (!(den[k] > options.epsilon)) continue;
    double updated = (*pattern)[k] * ratio(k);
    // NaN fails both comparisons and lands on the floor rather than passing through.
    (*pattern)[k] = updated >= 1.0 ? 1.0f : updated > floor ? static_cast<float>(updated) : floor;
  }
}
}  // namespace

void ApplyMultiplicativeStep(const double* num, const double* den, const SolverOptions& options,
                             std::vector<float>* pattern) {
  StepByRatio(den, options, pattern, [&](size_t k) { return num[k] / den[k]; });
}

void ApplyMultiplicativeStepFromResidual(const double* res, const double* den, const SolverOptions& options,
                                         std::vector<float>* pattern) {
  StepByRatio(den, options, pattern, [&](size_t k) { return MultiplicativeRatioFromResidual(res[k], den[k]); });
}

void ApplyLayerUpdate(const LayerUpdate& update, const SolverOptions& options, Patterns* t) {
  ApplyMultiplicativeStep(update.num->data(), update.den->data(), options, &(*t)[update.layer].rgb);
}

void UpdateLayerMultiplicative(const DisplayModel& model, size_t branch, int layer, const BranchTarget& branch_target,
                               const SolverOptions& options, Patterns* t, SolveWorkspace* workspace) {
  LayerUpdate update = OneLayerUpdate(workspace);
  ComputeLayerUpdate(model, {branch, layer}, branch_target, *t, workspace, &update);
  ApplyLayerUpdate(update, options, t);
}

void UpdateLayerFromPairs(const DisplayModel& model, size_t branch, int layer, const BranchPairs& pairs,
                          const SolverOptions& options, Patterns* t, SolveWorkspace* workspace) {
  LayerUpdate update = OneLayerUpdate(workspace);
  pairs.ComputeUpdate(model, branch, layer, *t, workspace, &update);
  ApplyLayerUpdate(update, options, t);
}

}  // namespace layerlab
