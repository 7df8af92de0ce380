// joint: every layer of every branch updated at once, from one pass over the
// rays per iteration (beyond the paper; compare it with `hybrid` on the
// error-against-time plot of `layerlab compare`).
//
// For the whole objective ||l - l~||^2, l~ = sum_b w_b prod_{k in b} P_k t_k,
// the gradient for layer a of branch b is 2 P_a^T((l~ - l) o Q_a) with
// Q_a = w_b prod_{k in b, k != a} P_k t_k. Splitting it into its positive and
// negative parts gives the multiplicative step (Lee-Seung, as tensor displays
// update their time-multiplexed frames)
//   t_a <- clamp(t_a * (P_a^T(l o Q_a) / P_a^T(l~ o Q_a))^alpha, floor, 1).
// The pass that sums those terms also yields ||l - l~||^2 of the iterate it
// reads, so an iteration costs one pass where the hybrid's costs
// 2 sets x 3 sub-iterations x 2 layers + 2 passes for the other sets' light.
//
// All layers of a branch moving at once multiply their ratios: a plain step
// uses alpha = 1 / (layers in the longest branch), which moves a uniformly
// wrong product exactly to the target. alpha over-relaxes that step: it grows
// by `kGrowth` after every iteration that lowered the objective, up to
// `kMaxRelaxation` times the plain one; an iterate that raised it is
// rejected: the previous iterate takes a plain step instead, from the ratios
// kept from its own pass, and alpha starts over.
//
// With the retinal objective (SolverOptions::objective) the pass is
// RetinalPass: the same step on the effective target L - M (L - l) / Bound(),
// whose sums are those of f / Bound() (retinal_pass.h). A negative numerator
// (the retinal residual outweighing the light) lands the value on the floor.
#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <vector>

#include "layerlab/kernels/joint_pass.h"
#include "layerlab/solvers/multiplicative_update.h"
#include "layerlab/solvers/retinal_pass.h"
#include "layerlab/solvers/solve_loop.h"

namespace layerlab {
namespace {

constexpr double kGrowth = 1.3;
constexpr double kMaxRelaxation = 8.0;

// ratio[k][i] = num / den = (den - res) / den, or 1 where the denominator is below epsilon.
void Ratios(const RayPass& pass, double epsilon, std::vector<std::vector<double>>* ratio) {
  const auto& res = pass.residual();
  const auto& den = pass.denominator();
  ratio->resize(res.size());
  for (size_t k = 0; k < res.size(); ++k) {
    (*ratio)[k].resize(res[k].size());
#pragma omp parallel for schedule(static)
    for (size_t i = 0; i < res[k].size(); ++i)
      (*ratio)[k][i] = den[k][i] > epsilon ? MultiplicativeRatioFromResidual(res[k][i], den[k][i]) : 1.0;
  }
}

// Elementwise, so the same bits for any thread count; threads because a
// power per value (a million of them for the paper's prototype) costs a
// good part of a pass.
void Step(const std::vector<std::vector<double>>& ratio, double alpha, float floor, Patterns* t) {
  for (size_t k = 0; k < t->size(); ++k) {
    std::vector<float>& p = (*t)[k].rgb;
#pragma omp parallel for schedule(static)
    for (size_t i = 0; i < p.size(); ++i) {
      const double r = alpha == 1.0 ? ratio[k][i] : std::pow(ratio[k][i], alpha);
      const double updated = p[i] * r;
      // NaN fails both comparisons and lands on the floor rather than passing through.
      p[i] = updated >= 1.0 ? 1.0f : updated > floor ? static_cast<float>(updated) : floor;
    }
  }
}

class JointSolver final : public Solver {
 public:
  SolverReport Solve(const DisplayModel& model, const LightField& target, const SolverOptions& options,
                     Patterns* t) const override {
    SolveLoop loop("joint", model, target, options, t);
    if (!loop.Start()) return loop.Finish();
    const LightField& l = loop.target();
    const float floor = static_cast<float>(options.floor);
    // The retinal objective's pass (retinal_pass.h) gives the same sums for f / Bound().
    std::optional<RetinalPass> retinal;
    std::unique_ptr<RayPass> pass;
    if (loop.retinal())
      retinal.emplace(model, l, *loop.retinal(), loop.diffraction(), loop.response());
    else
      pass = loop.MakePass();
    auto run = [&](const Patterns& p) { return retinal ? retinal->Run(p) : pass->Run(l, p); };
    const RayPass& sums = retinal ? retinal->sums() : *pass;

    std::vector<std::vector<double>> ratio, accepted_ratio;
    double accepted_objective = run(*t);
    Ratios(sums, options.epsilon, &accepted_ratio);
    Patterns accepted = *t;
    size_t longest = 1;
    for (size_t b = 0; b < model.branch_count(); ++b) longest = std::max(longest, model.branch_layers(b).size());
    const double plain_alpha = 1.0 / static_cast<double>(longest);
    double alpha = plain_alpha;
    bool plain = true;     // the step just taken was a plain one
    if (loop.resumed()) {  // continue as after the accepted iterate the checkpoint holds
      alpha = std::min(loop.ResumedState("alpha", plain_alpha) * kGrowth, kMaxRelaxation * plain_alpha);
      plain = false;
    }
    Step(accepted_ratio, alpha, floor, t);
    while (true) {
      const double objective = run(*t);
      Ratios(sums, options.epsilon, &ratio);
      if (!(objective <= accepted_objective)) {
        *t = accepted;
        if (plain) {  // even a plain step does not descend: round-off decides from here
          loop.Converge("no multiplicative step lowers the objective any more");
          break;
        }
        // Rejected: a plain step from the last accepted iterate instead.
        alpha = plain_alpha;
        Step(accepted_ratio, alpha, floor, t);
        plain = true;
        continue;
      }
      loop.SetState("alpha", alpha);
      if (retinal) loop.SetMeasures(retinal->last());
      if (!loop.EndIteration(objective)) break;
      accepted = *t;
      accepted_objective = objective;
      std::swap(accepted_ratio, ratio);
      alpha = std::min(alpha * kGrowth, kMaxRelaxation * plain_alpha);
      Step(accepted_ratio, alpha, floor, t);
      plain = false;
    }
    // *t holds the iterate the last recorded objective belongs to.
    return loop.Finish();
  }
};

}  // namespace

SolverType JointSolverType() {
  SolverOptions defaults;
  defaults.iterations = 200;
  SolverType type(
      "joint", "every layer of every branch at once, one pass per iteration, over-relaxed multiplicative steps",
      [] { return std::make_unique<JointSolver>(); }, defaults);
  type.retinal_objective = true;
  type.panel_diffraction = true;
  return type;
}

}  // namespace layerlab
