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

#include "layerlab/framework/huge_page_allocator.h"
#include "layerlab/kernels/joint_pass.h"
#include "layerlab/solvers/chunked_sweep.h"
#include "layerlab/solvers/hybrid_iterations.h"
#include "layerlab/solvers/retinal_pass.h"
#include "layerlab/solvers/solve_loop.h"

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
  void GradientAndScale(const RayPass& pass, const Vector& x, double scale, double epsilon, size_t begin, size_t end,
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

// One quasi-Newton solve: the warm start, then projected L-BFGS steps.
class QuasiNewtonRun {
 public:
  QuasiNewtonRun(const DisplayModel& model, const LightField& target, const SolverOptions& options, Patterns* t)
      : model_(model),
        options_(options),
        t_(t),
        loop_("quasi-newton", model, target, options, t),
        warm_iterations_(options.resume ? 0 : options.warm_start_iterations),
        lo_(options.floor) {
    if (warm_iterations_ > 0) warm_.emplace(model, options, t);  // the chase, allocated in the set-up
  }

  SolverReport Solve() {
    if (!loop_.Start()) return loop_.Finish();
    l_ = &loop_.target();
    size_t longest = 1;
    for (size_t b = 0; b < model_.branch_count(); ++b) longest = std::max(longest, model_.branch_layers(b).size());
    plain_ = 1.0 / static_cast<double>(longest);
    if (!loop_.retinal()) pass_ = loop_.MakePass();  // the retinal objective's pass has one of its own
    layout_.emplace(model_);
    n_ = layout_->size();
    spare_.resize(kMemory);
    if (!WarmStart()) return loop_.Finish();
    loop_.SetUpMidway([&] { MakeVectors(); });
    sums_ = retinal_ ? &retinal_->sums() : &*pass_;
    layout_->Gather(*t_, &x_);
    Sweep(n_, [&](size_t begin, size_t end) {
      layout_->GradientAndScale(*sums_, x_, plain_, options_.epsilon, begin, end, &g_, &h_);
    });
    while (Step()) {
    }
    return loop_.Finish();
  }

 private:
  // The retinal objective's pass (retinal_pass.h) gives the same sums for f / Bound().
  double Run(const Patterns& p) { return retinal_ ? retinal_->Run(p) : pass_->Run(*l_, p); }

  // The warm start, in this loop; its last iteration's patterns are
  // evaluated by the pass the first step needs, which also gives their
  // row. What the steps hold replaces the chase, made off the clock as
  // set-up: the retinal pass's light fields before that pass, the work
  // vectors after it, once the solve goes on. False when the loop ends.
  bool WarmStart() {
    if (warm_) warm_->Begin(&loop_);
    for (int k = 1; k <= warm_iterations_; ++k) {
      const bool last = k == warm_iterations_;
      // The hybrid's iterations see neither the panels' diffraction nor their response: their objective is
      // measured through them.
      std::optional<double> objective = warm_->Iterate(!last && loop_.plain_forward());
      if (!loop_.plain_forward()) objective.reset();
      if (last) {
        loop_.SetUpMidway([&] { MakePass(); });
        objective = f_ = Run(*t_);
        if (retinal_) loop_.SetMeasures(retinal_->last());
      }
      if (!loop_.EndIteration(objective)) return false;
    }
    if (warm_iterations_ == 0) {
      loop_.SetUpMidway([&] { MakePass(); });
      f_ = Run(*t_);
    }
    return true;
  }

  void MakePass() {
    warm_.reset();
    if (loop_.retinal()) retinal_.emplace(model_, *l_, *loop_.retinal(), loop_.diffraction(), loop_.response());
  }

  void MakeVectors() {
    for (Vector* v : {&x_, &g_, &h_, &d_, &x_new_, &g_new_, &h_new_, &free_, &change_}) v->resize(n_);
    for (Pair& p : spare_) p.s.resize(n_), p.y.resize(n_);
  }

  // One step; false when the solve ends.
  bool Step() {
    double slope = Direction(pairs_, g_, h_, x_, lo_, hi_, &free_, &d_);
    bool from_pairs = !pairs_.empty();
    if (!(slope < 0)) slope = PlainDirectionWithoutPairs(), from_pairs = false;
    if (!(slope < 0)) {
      loop_.Converge("the projected gradient is zero: a stationary point of the bounded problem");
      return false;
    }
    double f_new = f_;
    bool lowered = LineSearch(&f_new);
    if (!lowered && from_pairs) {  // the curvature pairs misled: the plain step before giving up
      PlainDirectionWithoutPairs();
      lowered = LineSearch(&f_new);
    }
    if (!lowered) {
      layout_->Scatter(x_, t_);
      loop_.Converge("no projected step lowers the objective any more");
      return false;
    }
    KeepPair();
    std::swap(x_, x_new_), std::swap(g_, g_new_), std::swap(h_, h_new_);
    f_ = f_new;
    if (retinal_) loop_.SetMeasures(retinal_->last());  // of x_new, the last patterns run
    return loop_.EndIteration(f_);
  }

  // Halves the projected step along d until it lowers the objective
  // enough; x_new, change and *f_new are then the step's. A step whose
  // slope clamping (or rounding) leaves non-negative is not evaluated.
  bool LineSearch(double* f_new) {
    for (int halving = 0; halving <= kMaxHalvings; ++halving) {
      const double slope =
          ProjectedStep(*layout_, x_, d_, g_, std::ldexp(1.0, -halving), lo_, hi_, &x_new_, &change_, t_);
      if (!(slope < 0)) continue;
      *f_new = Run(*t_);
      if (*f_new <= f_ + kArmijo * slope) return true;  // NaN fails: halved
    }
    return false;
  }

  // The plain step's direction, the pairs forgotten.
  double PlainDirectionWithoutPairs() {
    while (!pairs_.empty()) spare_.push_back(std::move(pairs_.front())), pairs_.pop_front();
    return PlainDirection(g_, h_, free_, &d_);
  }

  // The new gradient and scale, and the pair of this step; only pairs of
  // positive curvature keep H positive definite.
  void KeepPair() {
    Pair p = std::move(spare_.empty() ? pairs_.front() : spare_.back());
    if (spare_.empty())
      pairs_.pop_front();
    else
      spare_.pop_back();
    auto gradient_and_pair = [&](size_t begin, size_t end) {
      layout_->GradientAndScale(*sums_, x_new_, plain_, options_.epsilon, begin, end, &g_new_, &h_new_);
      for (size_t i = begin; i < end; ++i) p.s[i] = change_[i], p.y[i] = g_new_[i] - g_[i];
    };
    const auto [sy, ss, yy] = Sweep(
        n_, gradient_and_pair, [&](size_t i) { return p.s[i] * p.y[i]; }, [&](size_t i) { return p.s[i] * p.s[i]; },
        [&](size_t i) { return p.y[i] * p.y[i]; });
    if (sy > 1e-12 * std::sqrt(ss * yy)) {
      p.rho = 1.0 / sy;
      pairs_.push_back(std::move(p));
    } else {
      spare_.push_back(std::move(p));
    }
  }

  const DisplayModel& model_;
  const SolverOptions& options_;
  Patterns* t_;
  SolveLoop loop_;
  const int warm_iterations_;
  std::optional<HybridIterations> warm_;
  const LightField* l_ = nullptr;
  const double lo_, hi_ = 1.0;
  double plain_ = 1;  // the plain step's scale, 1 / layers of the longest branch
  std::unique_ptr<RayPass> pass_;
  std::optional<RetinalPass> retinal_;
  const RayPass* sums_ = nullptr;
  std::optional<Layout> layout_;
  size_t n_ = 0;
  Vector x_, g_, h_, d_, x_new_, g_new_, h_new_, free_, change_;
  std::deque<Pair> pairs_;
  std::vector<Pair> spare_;
  double f_ = 0;
};

class QuasiNewtonSolver final : public Solver {
 public:
  SolverReport Solve(const DisplayModel& model, const LightField& target, const SolverOptions& options,
                     Patterns* t) const override {
    return QuasiNewtonRun(model, target, options, t).Solve();
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
  type.panel_diffraction = true;
  type.lc_response = true;
  type.memory.layer_doubles = 9 + kMemory * 2;
  type.options = {{"warm_start_iterations", "iterations of hybrid before the quasi-Newton steps"}, SubIterationsKey()};
  return type;
}

}  // namespace layerlab
