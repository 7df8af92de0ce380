// quasi-newton: projected L-BFGS on every layer of every branch at once
// (beyond the paper). One pass over the rays (joint_pass.h) gives the
// objective and its gradient 2 res at the patterns it reads, so a
// step costs one pass, like a joint iteration; the curvature measured along
// the last few steps turns those gradients into steps that also move the
// layers of a branch against each other, which multiplicative steps (one
// scale per pixel) cannot.
//
// Bounds [floor, 1] by projection (Kim, Sra and Dhillon, "Tackling
// box-constrained optimization via a new projected quasi-Newton approach",
// 2010): values at a bound whose gradient pushes outward are held for the
// step; the others' direction comes from the two-loop recursion, started
// from the joint solver's plain multiplicative step, (1 / L) t / (2 den) per
// value (L: layers in the longest branch), scaled by the last pair's
// curvature; the projected step is halved until it lowers the objective
// enough (Armijo), so the objective never rises. Where no halving of the
// pairs' direction does, the plain step is tried before the solve stops.
//
// From a flat start the hybrid solver's first iterations gain more per
// second (each layer solved exactly against the others), so the first
// `warm_start_iterations` (default 2) are its; the quasi-Newton steps then
// go on from its patterns as from a checkpoint, with one trace and clock.
//
// With the retinal objective (SolverOptions::objective) the pass is
// RetinalPass, whose sums are those of f / Bound() (retinal_pass.h); the
// warm start is still the hybrid's light-field steps, its trace rows
// measured in the retinal objective.
#include <algorithm>
#include <cmath>
#include <deque>
#include <optional>
#include <vector>

#include "framework/huge_page_allocator.h"
#include "solvers/joint_pass.h"
#include "solvers/retinal_pass.h"
#include "solvers/solve_loop.h"
#include "solvers/solver_checkpoint.h"

namespace layerlab {
namespace {

constexpr size_t kMemory = 4;  // pairs kept: 3 to 20 converged alike per step on the dice
constexpr double kArmijo = 1e-4;
constexpr int kMaxHalvings = 30;

using Vector = std::vector<double, HugePageAllocator<double>>;

// Sums in fixed chunks added in order: the same bits for any thread count.
constexpr size_t kChunks = 64;

template <class Term>
double ChunkedSum(size_t n, Term term) {
  double part[kChunks] = {};
#pragma omp parallel for schedule(static)
  for (size_t c = 0; c < kChunks; ++c) {
    double s = 0;
    for (size_t i = n * c / kChunks; i < n * (c + 1) / kChunks; ++i) s += term(i);
    part[c] = s;
  }
  double total = 0;
  for (double p : part) total += p;
  return total;
}

double Dot(const Vector& a, const Vector& b) {
  return ChunkedSum(a.size(), [&](size_t i) { return a[i] * b[i]; });
}

// Every layer's values one after another.
class Layout {
 public:
  explicit Layout(const DisplayModel& model) {
    for (size_t k = 0; k < model.layer_count(); ++k) {
      offset_.push_back(size_);
      size_ += model.projection(k).pixel_count() * 3;
    }
  }
  size_t size() const { return size_; }

  void Gather(const Patterns& t, Vector* x) const {
    for (size_t k = 0; k < t.size(); ++k) std::copy(t[k].rgb.begin(), t[k].rgb.end(), x->begin() + offset_[k]);
  }
  void Scatter(const Vector& x, Patterns* t) const {
    for (size_t k = 0; k < t->size(); ++k) {
      float* out = (*t)[k].rgb.data();
      const double* in = x.data() + offset_[k];
#pragma omp parallel for schedule(static)
      for (size_t i = 0; i < (*t)[k].rgb.size(); ++i) out[i] = static_cast<float>(in[i]);
    }
  }
  // g = 2 res; h = scale * x / (2 den), 0 where den is below epsilon.
  void GradientAndScale(const JointPass& pass, const Vector& x, double scale, double epsilon, Vector* g,
                        Vector* h) const {
    for (size_t k = 0; k < offset_.size(); ++k) {
      const std::vector<double>& res = pass.residual()[k];
      const std::vector<double>& den = pass.denominator()[k];
#pragma omp parallel for schedule(static)
      for (size_t i = 0; i < res.size(); ++i) {
        const size_t j = offset_[k] + i;
        (*g)[j] = 2.0 * res[i];
        (*h)[j] = den[i] > epsilon ? scale * x[j] / (2.0 * den[i]) : 0.0;
      }
    }
  }

 private:
  std::vector<size_t> offset_;
  size_t size_ = 0;
};

// A step s and the change of gradient y it caused; rho = 1 / (s . y).
struct Pair {
  Vector s, y;
  double rho = 0;
};

// d = -H g over the free values (free[i] = 1, else 0), H the L-BFGS inverse
// Hessian from `pairs` started at gamma diag(h), gamma from the newest pair.
void Direction(const std::deque<Pair>& pairs, const Vector& g, const Vector& h, const Vector& free, Vector* d) {
  const size_t n = g.size();
  Vector& q = *d;
#pragma omp parallel for schedule(static)
  for (size_t i = 0; i < n; ++i) q[i] = g[i] * free[i];
  double a[kMemory + 1];
  for (size_t j = pairs.size(); j-- > 0;) {
    const Pair& p = pairs[j];
    a[j] = p.rho * Dot(p.s, q);
#pragma omp parallel for schedule(static)
    for (size_t i = 0; i < n; ++i) q[i] -= a[j] * p.y[i] * free[i];
  }
  double gamma = 1.0;
  if (!pairs.empty()) {  // s.y / y.H0.y of the newest pair
    const Pair& p = pairs.back();
    const double yhy = ChunkedSum(n, [&](size_t i) { return p.y[i] * h[i] * p.y[i] * free[i]; });
    if (yhy > 0) gamma = 1.0 / (p.rho * yhy);
  }
#pragma omp parallel for schedule(static)
  for (size_t i = 0; i < n; ++i) q[i] *= gamma * h[i];
  for (size_t j = 0; j < pairs.size(); ++j) {
    const Pair& p = pairs[j];
    const double b = p.rho * Dot(p.y, q);
#pragma omp parallel for schedule(static)
    for (size_t i = 0; i < n; ++i) q[i] += (a[j] - b) * p.s[i] * free[i];
  }
#pragma omp parallel for schedule(static)
  for (size_t i = 0; i < n; ++i) q[i] = -q[i] * free[i];
}

// x_new = clamp(x + step d, lo, hi), rounded to float as the patterns are
// (so that the pairs see the step the patterns took); change = x_new - x.
void ProjectedStep(const Vector& x, const Vector& d, double step, double lo, double hi, Vector* x_new, Vector* change) {
#pragma omp parallel for schedule(static)
  for (size_t i = 0; i < x.size(); ++i) {
    (*x_new)[i] = static_cast<float>(std::clamp(x[i] + step * d[i], lo, hi));
    (*change)[i] = (*x_new)[i] - x[i];
  }
}

// d = -h g over the free values: the plain multiplicative step's direction.
void PlainDirection(const Vector& g, const Vector& h, const Vector& free, Vector* d) {
#pragma omp parallel for schedule(static)
  for (size_t i = 0; i < g.size(); ++i) (*d)[i] = -h[i] * g[i] * free[i];
}

class QuasiNewtonSolver final : public Solver {
 public:
  SolverReport Solve(const DisplayModel& model, const LightField& target, const SolverOptions& options,
                     Patterns* t) const override {
    if (options.warm_start_iterations == 0 || options.resume) return QuasiNewton(model, target, options, t);
    // The hybrid runs under this solve's options, asked to stop after its share.
    SolverOptions first = options;
    first.checkpoint = nullptr;  // written below, as this solver's
    first.checkpoint_every = 0;
    int asked = 0;
    bool warm_done = false;
    first.interrupted = [&] {
      if (options.interrupted && options.interrupted()) return true;
      return warm_done = ++asked >= options.warm_start_iterations;
    };
    SolverReport warm = SolverRegistry::Builtins().create("hybrid")->Solve(model, target, first, t);
    warm.solver = "quasi-newton";
    SolverCheckpoint start{"quasi-newton", warm.iterations, warm.seconds, *t, {}, warm.trace};
    // The budget is checked after the stop request: a warm start that used it up ends the solve too.
    if (warm_done && options.time_budget > 0 && warm.seconds >= options.time_budget) {
      warm.termination = Termination::kTimeBudget;
      warm.message = TimeBudgetMessage(warm.seconds);
      warm_done = false;
    }
    if (!warm_done) {  // stopped where this solve stops: its limit, budget, interruption, or a failure
      const bool short_stop =
          warm.termination == Termination::kInterrupted || warm.termination == Termination::kTimeBudget;
      if (short_stop && options.checkpoint && options.checkpoint_every > 0) options.checkpoint(start);
      return warm;
    }
    SolverOptions rest = options;
    rest.resume = &start;
    SolverReport report = QuasiNewton(model, target, rest, t);
    report.setup_seconds += warm.setup_seconds;
    return report;
  }

 private:
  SolverReport QuasiNewton(const DisplayModel& model, const LightField& target, const SolverOptions& options,
                           Patterns* t) const {
    SolveLoop loop("quasi-newton", model, target, options, t);
    // Work vectors allocated and touched in the set-up.
    const Layout layout(model);
    const size_t n = layout.size();
    Vector x(n), g(n), h(n), d(n), x_new(n), g_new(n), h_new(n), free(n), change(n);
    std::deque<Pair> pairs;
    std::vector<Pair> spare(kMemory);
    for (Pair& p : spare) p.s.resize(n), p.y.resize(n);
    if (!loop.Start()) return loop.Finish();
    const LightField& l = loop.target();
    const double lo = options.floor, hi = 1.0;
    size_t longest = 1;
    for (size_t b = 0; b < model.branch_count(); ++b) longest = std::max(longest, model.branch_layers(b).size());
    const double plain = 1.0 / static_cast<double>(longest);
    JointPass pass(model, &loop.workspace());
    // The retinal objective's pass (retinal_pass.h) gives the same sums for f / Bound().
    std::optional<RetinalPass> retinal;
    if (loop.retinal()) retinal.emplace(model, l, *loop.retinal());
    auto run = [&](const Patterns& p) { return retinal ? retinal->Run(p) : pass.Run(l, p); };
    const JointPass& sums = retinal ? retinal->sums() : pass;

    layout.Gather(*t, &x);
    double f = run(*t);
    layout.GradientAndScale(sums, x, plain, options.epsilon, &g, &h);
    // Halves the projected step along d until it lowers the objective
    // enough; x_new, change and *f_new are then the step's. A step whose
    // slope clamping (or rounding) leaves non-negative is not evaluated.
    auto line_search = [&](double* f_new) {
      for (int halving = 0; halving <= kMaxHalvings; ++halving) {
        ProjectedStep(x, d, std::ldexp(1.0, -halving), lo, hi, &x_new, &change);
        const double slope = Dot(g, change);
        if (!(slope < 0)) continue;
        layout.Scatter(x_new, t);
        *f_new = run(*t);
        if (*f_new <= f + kArmijo * slope) return true;  // NaN fails: halved
      }
      return false;
    };
    // The plain step's direction, the pairs forgotten.
    auto plain_direction = [&] {
      while (!pairs.empty()) spare.push_back(std::move(pairs.front())), pairs.pop_front();
      PlainDirection(g, h, free, &d);
    };

    while (true) {
#pragma omp parallel for schedule(static)
      for (size_t i = 0; i < n; ++i)
        free[i] = h[i] > 0 && !(x[i] <= lo && g[i] > 0) && !(x[i] >= hi && g[i] < 0) ? 1.0 : 0.0;
      Direction(pairs, g, h, free, &d);
      bool from_pairs = !pairs.empty();
      if (!(Dot(g, d) < 0)) plain_direction(), from_pairs = false;
      if (!(Dot(g, d) < 0)) {
        loop.Converge("the projected gradient is zero: a stationary point of the bounded problem");
        break;
      }
      double f_new = f;
      bool lowered = line_search(&f_new);
      if (!lowered && from_pairs) {  // the curvature pairs misled: the plain step before giving up
        plain_direction();
        lowered = line_search(&f_new);
      }
      if (!lowered) {
        layout.Scatter(x, t);
        loop.Converge("no projected step lowers the objective any more");
        break;
      }
      layout.GradientAndScale(sums, x_new, plain, options.epsilon, &g_new, &h_new);

      Pair p = std::move(spare.empty() ? pairs.front() : spare.back());
      if (spare.empty())
        pairs.pop_front();
      else
        spare.pop_back();
#pragma omp parallel for schedule(static)
      for (size_t i = 0; i < n; ++i) p.s[i] = change[i], p.y[i] = g_new[i] - g[i];
      const double sy = Dot(p.s, p.y);
      // Only pairs of positive curvature keep H positive definite.
      if (sy > 1e-12 * std::sqrt(Dot(p.s, p.s) * Dot(p.y, p.y))) {
        p.rho = 1.0 / sy;
        pairs.push_back(std::move(p));
      } else {
        spare.push_back(std::move(p));
      }
      std::swap(x, x_new), std::swap(g, g_new), std::swap(h, h_new);
      f = f_new;
      if (retinal) loop.SetMeasures(retinal->last());  // of x_new, the last patterns run
      if (!loop.EndIteration(f)) break;
    }
    return loop.Finish();
  }
};

}  // namespace

SolverType QuasiNewtonSolverType() {
  SolverOptions defaults;
  defaults.iterations = 200;
  defaults.warm_start_iterations = 2;
  SolverType type(
      "quasi-newton",
      "projected L-BFGS on every layer at once after warm_start_iterations of hybrid, one pass per step",
      [] { return std::make_unique<QuasiNewtonSolver>(); }, defaults);
  // The warm start's chase; 9 work vectors and kMemory pairs of 2, in double.
  type.memory.light_fields = 1;
  type.retinal_objective = true;
  type.memory.layer_doubles = 9 + kMemory * 2;
  type.options = {{"warm_start_iterations", "iterations of hybrid before the quasi-Newton steps"}, SubIterationsKey()};
  return type;
}

}  // namespace layerlab
