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
// `warm_start_iterations` (default 2) are its (solvers/hybrid_iterations.h),
// in this solve's loop, trace and workspace. The last of them skips the
// hybrid's objective pass: the joint pass the first step needs gives its
// row. A resumed solve goes on with quasi-Newton steps.
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
#include "kernels/joint_pass.h"
#include "solvers/chunked_sweep.h"
#include "solvers/hybrid_iterations.h"
#include "solvers/retinal_pass.h"
#include "solvers/solve_loop.h"

namespace layerlab {
namespace {

constexpr size_t kMemory = 4;  // pairs kept: 3 to 20 converged alike per step on the dice
constexpr double kArmijo = 1e-4;
constexpr int kMaxHalvings = 30;

using Vector = std::vector<double, HugePageAllocator<double>>;

// Every layer's values one after another.
class Layout {
 public:
  explicit Layout(const DisplayModel& model) {
    for (size_t k = 0; k < model.layer_count(); ++k) {
      offset_.push_back(size_);
      size_ += model.projection(k).pixel_count() * 3;
    }
    offset_.push_back(size_);
  }
  size_t size() const { return size_; }

  void Gather(const Patterns& t, Vector* x) const {
    for (size_t k = 0; k < t.size(); ++k) std::copy(t[k].rgb.begin(), t[k].rgb.end(), x->begin() + offset_[k]);
  }
  // Each layer's part of [begin, end): at(layer, index in the layer, index in x).
  template <class At>
  void ForRange(size_t begin, size_t end, At at) const {
    for (size_t k = 0; k + 1 < offset_.size(); ++k) {
      const size_t from = std::max(begin, offset_[k]), to = std::min(end, offset_[k + 1]);
      for (size_t j = from; j < to; ++j) at(k, j - offset_[k], j);
    }
  }
  // The patterns' values [begin, end) from x.
  void Scatter(const Vector& x, size_t begin, size_t end, Patterns* t) const {
    ForRange(begin, end, [&](size_t k, size_t i, size_t j) { (*t)[k].rgb[i] = static_cast<float>(x[j]); });
  }
  void Scatter(const Vector& x, Patterns* t) const {
    Sweep(x.size(), [&](size_t begin, size_t end) { Scatter(x, begin, end, t); });
  }
  // g = 2 res; h = scale * x / (2 den), 0 where den is below epsilon; over [begin, end).
  void GradientAndScale(const JointPass& pass, const Vector& x, double scale, double epsilon, size_t begin, size_t end,
                        Vector* g, Vector* h) const {
    ForRange(begin, end, [&](size_t k, size_t i, size_t j) {
      const double res = pass.residual()[k][i], den = pass.denominator()[k][i];
      (*g)[j] = 2.0 * res;
      (*h)[j] = den > epsilon ? scale * x[j] / (2.0 * den) : 0.0;
    });
  }

 private:
  std::vector<size_t> offset_;  // [layer], and the size last
  size_t size_ = 0;
};

// A step s and the change of gradient y it caused; rho = 1 / (s . y).
struct Pair {
  Vector s, y;
  double rho = 0;
};

// free[i] = 1 where value i may move (h > 0 and not held at a bound its
// gradient pushes it past), else 0; then d = -H g over the free values, H
// the L-BFGS inverse Hessian from `pairs` started at gamma diag(h), gamma
// from the newest pair. Returns g . d. Each sweep ends with the dot product
// the next one needs.
double Direction(const std::deque<Pair>& pairs, const Vector& g, const Vector& h, const Vector& x, double lo, double hi,
                 Vector* free_values, Vector* d) {
  const size_t n = g.size(), m = pairs.size();
  Vector& q = *d;
  Vector& free = *free_values;
  auto start = Each([&](size_t i) {
    free[i] = h[i] > 0 && !(x[i] <= lo && g[i] > 0) && !(x[i] >= hi && g[i] < 0) ? 1.0 : 0.0;
    q[i] = g[i] * free[i];
  });
  if (m == 0) {  // H = diag(h): gamma 1
    constexpr double kGamma = 1.0;
    auto plain = [&](size_t begin, size_t end) {
      start(begin, end);
      for (size_t i = begin; i < end; ++i) q[i] *= kGamma * h[i], q[i] = -q[i] * free[i];
    };
    return Sweep(n, plain, [&](size_t i) { return g[i] * q[i]; })[0];
  }
  // The first loop, newest pair first: a_j = rho_j s_j . q, q -= a_j y_j.
  const Pair& newest = pairs.back();
  const auto [newest_sq, yhy] = Sweep(
      n, start, [&](size_t i) { return newest.s[i] * q[i]; },
      [&](size_t i) { return newest.y[i] * h[i] * newest.y[i] * free[i]; });
  const double gamma = yhy > 0 ? 1.0 / (newest.rho * yhy) : 1.0;  // s.y / y.H0.y of the newest pair
  double a[kMemory + 1];
  double sq = newest_sq;
  for (size_t j = m; j-- > 0;) {
    const Pair& p = pairs[j];
    const double aj = a[j] = p.rho * sq;
    auto update = Each([&](size_t i) { q[i] -= aj * p.y[i] * free[i]; });
    if (j > 0) {
      const Pair& next = pairs[j - 1];
      sq = Sweep(n, update, [&](size_t i) { return next.s[i] * q[i]; })[0];
    } else {  // then q = gamma H0 q, and the second loop's first y . q
      auto scale = [&](size_t begin, size_t end) {
        update(begin, end);
        for (size_t i = begin; i < end; ++i) q[i] *= gamma * h[i];
      };
      sq = Sweep(n, scale, [&](size_t i) { return pairs[0].y[i] * q[i]; })[0];
    }
  }
  // The second loop, oldest pair first: b = rho_j y_j . q, q += (a_j - b) s_j; then d = -q.
  for (size_t j = 0; j + 1 < m; ++j) {
    const Pair& p = pairs[j];
    const double coefficient = a[j] - p.rho * sq;
    const Pair& next = pairs[j + 1];
    sq = Sweep(n, Each([&](size_t i) { q[i] += coefficient * p.s[i] * free[i]; }),
               [&](size_t i) { return next.y[i] * q[i]; })[0];
  }
  const double coefficient = a[m - 1] - newest.rho * sq;
  auto last = Each([&](size_t i) {
    q[i] += coefficient * newest.s[i] * free[i];
    q[i] = -q[i] * free[i];
  });
  return Sweep(n, last, [&](size_t i) { return g[i] * q[i]; })[0];
}

// d = -h g over the free values: the plain multiplicative step's direction. Returns g . d.
double PlainDirection(const Vector& g, const Vector& h, const Vector& free, Vector* d) {
  return Sweep(g.size(), Each([&](size_t i) { (*d)[i] = -h[i] * g[i] * free[i]; }),
               [&](size_t i) { return g[i] * (*d)[i]; })[0];
}

// x_new = clamp(x + step d, lo, hi), rounded to float as the patterns are
// (so that the pairs see the step the patterns took), and written into the
// patterns; change = x_new - x. Returns g . change.
double ProjectedStep(const Layout& layout, const Vector& x, const Vector& d, const Vector& g, double step, double lo,
                     double hi, Vector* x_new, Vector* change, Patterns* t) {
  auto body = [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) {
      (*x_new)[i] = static_cast<float>(std::clamp(x[i] + step * d[i], lo, hi));
      (*change)[i] = (*x_new)[i] - x[i];
    }
    layout.Scatter(*x_new, begin, end, t);
  };
  return Sweep(x.size(), body, [&](size_t i) { return g[i] * (*change)[i]; })[0];
}

class QuasiNewtonSolver final : public Solver {
 public:
  SolverReport Solve(const DisplayModel& model, const LightField& target, const SolverOptions& options,
                     Patterns* t) const override {
    SolveLoop loop("quasi-newton", model, target, options, t);
    const int warm_iterations = options.resume ? 0 : options.warm_start_iterations;
    std::optional<HybridIterations> warm;
    if (warm_iterations > 0) warm.emplace(model, options, t);  // the chase, allocated in the set-up
    if (!loop.Start()) return loop.Finish();
    const LightField& l = loop.target();
    const double lo = options.floor, hi = 1.0;
    size_t longest = 1;
    for (size_t b = 0; b < model.branch_count(); ++b) longest = std::max(longest, model.branch_layers(b).size());
    const double plain = 1.0 / static_cast<double>(longest);
    JointPass pass(model, &loop.workspace());
    // The retinal objective's pass (retinal_pass.h) gives the same sums for f / Bound().
    std::optional<RetinalPass> retinal;
    auto run = [&](const Patterns& p) { return retinal ? retinal->Run(p) : pass.Run(l, p); };

    // The warm start, in this loop; its last iteration's patterns are
    // evaluated by the pass the first step needs, which also gives their
    // row. What the steps hold replaces the chase, made off the clock as
    // set-up: the retinal pass's light fields before that pass, the work
    // vectors after it, once the solve goes on.
    const Layout layout(model);
    const size_t n = layout.size();
    Vector x, g, h, d, x_new, g_new, h_new, free, change;
    std::deque<Pair> pairs;
    std::vector<Pair> spare(kMemory);
    auto make_pass = [&] {
      warm.reset();
      if (loop.retinal()) retinal.emplace(model, l, *loop.retinal());
    };
    auto make_vectors = [&] {
      for (Vector* v : {&x, &g, &h, &d, &x_new, &g_new, &h_new, &free, &change}) v->resize(n);
      for (Pair& p : spare) p.s.resize(n), p.y.resize(n);
    };
    double f = 0;
    if (warm) warm->Begin(&loop);
    for (int k = 1; k <= warm_iterations; ++k) {
      const bool last = k == warm_iterations;
      std::optional<double> objective = warm->Iterate(!last);
      if (last) {
        loop.SetUpMidway(make_pass);
        objective = f = run(*t);
        if (retinal) loop.SetMeasures(retinal->last());
      }
      if (!loop.EndIteration(objective)) return loop.Finish();
    }
    if (warm_iterations == 0) {
      loop.SetUpMidway(make_pass);
      f = run(*t);
    }
    loop.SetUpMidway(make_vectors);
    const JointPass& sums = retinal ? retinal->sums() : pass;
    layout.Gather(*t, &x);
    Sweep(n, [&](size_t begin, size_t end) {
      layout.GradientAndScale(sums, x, plain, options.epsilon, begin, end, &g, &h);
    });
    // Halves the projected step along d until it lowers the objective
    // enough; x_new, change and *f_new are then the step's. A step whose
    // slope clamping (or rounding) leaves non-negative is not evaluated.
    auto line_search = [&](double* f_new) {
      for (int halving = 0; halving <= kMaxHalvings; ++halving) {
        const double slope = ProjectedStep(layout, x, d, g, std::ldexp(1.0, -halving), lo, hi, &x_new, &change, t);
        if (!(slope < 0)) continue;
        *f_new = run(*t);
        if (*f_new <= f + kArmijo * slope) return true;  // NaN fails: halved
      }
      return false;
    };
    // The plain step's direction, the pairs forgotten.
    auto plain_direction = [&] {
      while (!pairs.empty()) spare.push_back(std::move(pairs.front())), pairs.pop_front();
      return PlainDirection(g, h, free, &d);
    };

    while (true) {
      double slope = Direction(pairs, g, h, x, lo, hi, &free, &d);
      bool from_pairs = !pairs.empty();
      if (!(slope < 0)) slope = plain_direction(), from_pairs = false;
      if (!(slope < 0)) {
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
      Pair p = std::move(spare.empty() ? pairs.front() : spare.back());
      if (spare.empty())
        pairs.pop_front();
      else
        spare.pop_back();
      // The new gradient and scale, and the pair of this step.
      auto gradient_and_pair = [&](size_t begin, size_t end) {
        layout.GradientAndScale(sums, x_new, plain, options.epsilon, begin, end, &g_new, &h_new);
        for (size_t i = begin; i < end; ++i) p.s[i] = change[i], p.y[i] = g_new[i] - g[i];
      };
      const auto [sy, ss, yy] = Sweep(
          n, gradient_and_pair, [&](size_t i) { return p.s[i] * p.y[i]; }, [&](size_t i) { return p.s[i] * p.s[i]; },
          [&](size_t i) { return p.y[i] * p.y[i]; });
      // Only pairs of positive curvature keep H positive definite.
      if (sy > 1e-12 * std::sqrt(ss * yy)) {
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
  // The warm start's chase, then 9 work vectors and kMemory pairs of 2, in double.
  type.memory.light_fields = 1;
  type.memory.fields_then_layers = true;
  type.retinal_objective = true;
  type.memory.layer_doubles = 9 + kMemory * 2;
  type.options = {{"warm_start_iterations", "iterations of hybrid before the quasi-Newton steps"}, SubIterationsKey()};
  return type;
}

}  // namespace layerlab
