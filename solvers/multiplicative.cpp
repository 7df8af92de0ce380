// multiplicative: the non-negative update rules for a display of one branch
// (a stack of any number of layers), each iteration updating every layer once,
// from the farthest to the nearest.
//
// A time-multiplexed stack (one branch per subframe, K subframes) is the
// rank-K factorization of tensor displays (Wetzstein et al. 2012): the
// layers at one depth of every subframe are updated at once, against the
// time average l~ = sum_k w_k prod_{j in k} P_j t_j of all subframes,
//   t_a <- clamp(t_a * P_a^T(l o Q_a) / P_a^T(l~ o Q_a), floor, 1),   Q_a = w_k prod_{j in k, j != a} P_j t_j,
// a Lee-Seung step of the whole objective (l~ is linear in those K layers
// together, no subframe holding two of them), then the next depth from a
// new pass. One pass (joint_pass.h) gives the sums and the objective of the
// patterns it reads, so an iteration costs one pass per layer of the stack;
// on the one-tap path it sums only the depth updated next.
//
// A stack of two one-tap layers whose rays are at least twice their pixel
// pairs (kernels/pair_lattice.h) bins the target once; the second layer's
// updates are then made from the pairs, the first's (with the objective)
// from a pass over the rays.
//
// Through the panels' diffraction (SolverOptions::panel_diffraction) every
// stack takes the depth-by-depth path, whose joint pass reads the diffracted
// patterns D t and maps its sums back by D^T: the convolutive form of the
// same step, t_a <- t_a * D_a^T(num) / D_a^T(den), D_a >= 0.
#include <algorithm>
#include <memory>
#include <optional>

#include "layerlab/framework/error.h"
#include "layerlab/kernels/joint_pass.h"
#include "layerlab/solvers/multiplicative_update.h"
#include "layerlab/solvers/objective.h"
#include "layerlab/solvers/solve_loop.h"
#include "layerlab/systems/source_spread.h"

namespace layerlab {
namespace {

std::string Unsuitable(const DisplaySystem& system) {
  const size_t branches = system.branches.size();
  if (branches == 1) return "";
  if (system.subframes == 1)
    return "needs a display of one branch; this one has " + std::to_string(branches) + " (use hybrid)";
  if (branches != static_cast<size_t>(system.subframes))
    return "needs one branch per subframe (a stack shown K times); this one has " + std::to_string(branches) +
           " branches in " + std::to_string(system.subframes) + " subframes (use hybrid)";
  if (system.branches[0].layers.size() < 2)
    return "needs a stack of layers in each subframe; this display shows one layer per subframe, additive over "
           "time (use additive-trust-region)";
  return "";
}

// [depth][subframe]: each subframe's layers from the farthest to the nearest.
std::vector<std::vector<int>> LayersByDepth(const DisplayModel& model) {
  std::vector<std::vector<int>> by_depth;
  for (size_t b = 0; b < model.branch_count(); ++b) {
    std::vector<int> order = model.branch_layers(b);
    std::sort(order.begin(), order.end());
    by_depth.resize(order.size());
    for (size_t p = 0; p < order.size(); ++p) by_depth[p].push_back(order[p]);
  }
  return by_depth;
}

// One pass over the rays: the objective of `t` and the sums of the layers
// at one depth. On the one-tap path only those layers are summed (a rank-1
// iteration sums one layer per pass, so a rank-K one should sum K, not 2K).
class DepthPass {
 public:
  DepthPass(const DisplayModel& model, const std::vector<std::vector<int>>& by_depth, SolveLoop* loop)
      : pass_(loop->MakePass()) {
    for (const std::vector<int>& layers : by_depth) {
      summed_.emplace_back(model.layer_count(), 0);
      for (int a : layers) summed_.back()[a] = 1;
    }
  }
  // Without `objective` the one-tap path leaves it out and returns 0.
  double Run(const LightField& l, const Patterns& t, size_t depth, bool objective) {
    return pass_->Run(l, t, &summed_[depth], objective);
  }
  const double* residual(int layer) const { return pass_->residual()[layer].data(); }
  const double* denominator(int layer) const { return pass_->denominator()[layer].data(); }

 private:
  std::unique_ptr<RayPass> pass_;
  std::vector<std::vector<char>> summed_;  // [depth][layer]
};

// The rank-K iterations (K > 1 subframes), and any stack through the panels' diffraction or an LED array's
// spread (its sites' step is the same Lee-Seung step through S: L <- L * S^T(num) / S^T(den)).
void SolveByDepth(const DisplayModel& model, const SolverOptions& options, SolveLoop* loop, Patterns* t) {
  const LightField& l = loop->target();
  const std::vector<std::vector<int>> by_depth = LayersByDepth(model);
  DepthPass pass(model, by_depth, loop);
  auto step = [&](size_t depth) {
    for (int a : by_depth[depth])
      if (!IsFixedLayer(model, static_cast<size_t>(a))) {
        ApplyMultiplicativeStepFromResidual(pass.residual(a), pass.denominator(a), options, &(*t)[a].rgb);
        KeepEmitterSites(model.system().layers[a], &(*t)[a].rgb);  // the floor would lift the pixels between
      }
  };
  // The pass that gives an iteration's objective also gives the sums of
  // the next iteration's first step, applied only if there is one.
  pass.Run(l, *t, 0, /*objective=*/false);
  double objective = 0;
  do {
    step(0);
    for (size_t p = 1; p < by_depth.size(); ++p) {
      pass.Run(l, *t, p, /*objective=*/false);
      step(p);
    }
    objective = pass.Run(l, *t, 0, /*objective=*/true);
  } while (loop->EndIteration(objective));
}

class MultiplicativeSolver final : public Solver {
 public:
  SolverReport Solve(const DisplayModel& model, const LightField& target, const SolverOptions& options,
                     Patterns* t) const override {
    SolveLoop loop("multiplicative", model, target, options, t);
    const std::string why = Unsuitable(model.system());
    if (!loop.Start(why.empty() ? why : "the multiplicative solver " + why)) return loop.Finish();
    if (model.branch_count() > 1 || !loop.plain_forward()) {
      SolveByDepth(model, options, &loop, t);
      return loop.Finish();
    }
    const LightField& l = loop.target();
    BranchTarget whole = [&](size_t view, float*) { return l.view(view); };
    std::vector<int> order = model.branch_layers(0);
    std::sort(order.begin(), order.end());
    // The pass that gives an iteration's objective also gives the sums of the
    // next iteration's first update (both read the same patterns), which is
    // applied only if there is a next iteration.
    SolveWorkspace* workspace = &loop.workspace();
    // A stack of two layers whose rays repeat pixel pairs bins the target
    // once and makes the second layer's updates from the pairs (pair_lattice.h).
    const std::optional<BranchPairs> pairs = BranchPairs::IfItPays(model, 0);
    if (pairs) pairs->Bin(l, workspace);
    LayerUpdate first = KeptLayerUpdate(workspace);
    ComputeLayerUpdate(model, {0, order[0]}, whole, *t, workspace, &first);
    std::optional<double> objective;
    // A fixed layer (a printed mask) is read, never updated; the first's pass still gives the objective.
    const bool first_fixed = IsFixedLayer(model, static_cast<size_t>(order[0]));
    do {
      if (!first_fixed) ApplyLayerUpdate(first, options, t);
      for (size_t k = 1; k < order.size(); ++k) {
        if (IsFixedLayer(model, static_cast<size_t>(order[k]))) continue;
        if (pairs)
          UpdateLayerFromPairs(model, 0, order[k], *pairs, options, t, workspace);
        else
          UpdateLayerMultiplicative(model, 0, order[k], whole, options, t, workspace);
      }
      double error = 0;
      const bool fused = ComputeLayerUpdate(model, {0, order[0]}, whole, *t, workspace, &first, &error);
      objective = fused ? std::optional<double>(error) : std::nullopt;
    } while (loop.EndIteration(objective));
    return loop.Finish();
  }
};

}  // namespace

SolverType MultiplicativeSolverType() {
  SolverOptions defaults;
  defaults.iterations = 90;  // as many updates of each layer as the hybrid's 30 x 3
  SolverType type(
      "multiplicative",
      "non-negative multiplicative update rules for one stack of any number of layers, shown in K subframes "
      "as a rank-K factorization",
      [] { return std::make_unique<MultiplicativeSolver>(); }, defaults);
  type.unsuitable = Unsuitable;
  type.default_rank = 3;
  type.panel_diffraction = true;
  type.fixed_layers = true;
  // The joint pass for rank K; the pair lattice for a stack of two.
  type.memory.passes = kSynthesisPass | kLayerUpdatePass | kJointPassIfBranches | kPairLatticeIfOneBranch;
  return type;
}

}  // namespace layerlab
