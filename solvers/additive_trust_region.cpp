// additive-trust-region: the box-constrained linear least squares of an
// additive display (every branch a single layer),
//   min_t || l - A t ||^2,  A t = sum_b w_b P_b t_b,  0 <= t <= 1,
// by a matrix-free projected trust-region Newton-CG method (in the manner of
// TRON, Lin & More 1999): at each iteration the variables held at a bound by
// the gradient are fixed, a Steihaug conjugate-gradient step on the others
// (Hessian 2 A^T A applied as P and P^T passes, never stored) is bounded by
// the trust radius, and a projected backtracking search keeps the iterate in
// the box. Why not Ceres: at paper scale the problem has 40 M residuals of
// two parameters each; Ceres would store that Jacobian (about 80 M entries
// plus per-residual-block overhead, several GB) where this stores vectors of
// the size of the layers.
//
// When every layer is separable (no rotation) the whole solve runs in layer
// space (additive_gram.h): A^T l and ||l||^2 are summed over the rays once,
// and every objective, gradient and Hessian product after that comes from
// the Kronecker-factored normal matrix. Rotated layers take a pass over the
// rays for each.
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "layerlab/framework/fixed_parts.h"
#include "layerlab/framework/mpi_ranks.h"
#include "layerlab/solvers/additive_gram.h"
#include "layerlab/solvers/solve_loop.h"

namespace layerlab {
namespace {

// A vector over all layer pixels and channels (one block per layer).
using Vec = std::vector<std::vector<double>>;

Vec Zeros(const Patterns& shape) {
  Vec v;
  for (const LayerPattern& p : shape) v.emplace_back(p.rgb.size(), 0.0);
  return v;
}
// Four partial sums, by index mod 4, added at the end: a single running
// sum waits on each add's latency, four proceed side by side (the layer-space
// solve is mostly these sums). A fixed order: the same bits on any machine.
double Dot(const Vec& a, const Vec& b) {
  double s[4] = {};
  for (size_t k = 0; k < a.size(); ++k) {
    const double* x = a[k].data();
    const double* y = b[k].data();
    const size_t n = a[k].size();
    size_t i = 0;
    for (; i + 4 <= n; i += 4)
      for (int q = 0; q < 4; ++q) s[q] += x[i + q] * y[i + q];
    for (; i < n; ++i) s[i % 4] += x[i] * y[i];
  }
  return (s[0] + s[1]) + (s[2] + s[3]);
}
void Axpy(double alpha, const Vec& x, Vec* y) {
  for (size_t k = 0; k < x.size(); ++k)
    for (size_t i = 0; i < x[k].size(); ++i) (*y)[k][i] += alpha * x[k][i];
}

// Sums over views cut into fixed parts (a static schedule's shares), each
// part's kept apart and added in part order: the same bits on any team of at
// most that many threads (framework/fixed_parts.h), where a critical section
// or a reduction adds in the order the threads arrive.
class PartSums {
 public:
  PartSums() : parts_(FixedParts()) {}
  int parts() const { return static_cast<int>(parts_.size()); }
  // Part p's sums, zero.
  Vec* Part(int p, const Patterns& shape) {
    parts_[p] = Zeros(shape);
    return &parts_[p];
  }
  void SumInPartOrder(const Patterns& shape, Vec* out) const {
    *out = Zeros(shape);
    for (const Vec& part : parts_) Axpy(1.0, part, out);
  }

 private:
  std::vector<Vec> parts_;
};

class AdditiveOperator {
 public:
  explicit AdditiveOperator(const DisplayModel& model) : model_(model), n_(model.geometry().pixels_per_view() * 3) {}

  // Into one view: (A x) where x is given as float patterns.
  void Apply(size_t view, const Patterns& x, float* out, float* scratch) const {
    std::fill(out, out + n_, 0.0f);
    for (size_t b = 0; b < model_.branch_count(); ++b) {
      int k = model_.branch_layers(b)[0];
      model_.projection(k).Gather(view, x[k].rgb.data(), scratch);
      const auto& w = model_.weight(b);
      for (size_t i = 0; i < n_; ++i) out[i] += w[i % 3] * scratch[i];
    }
  }
  // accum += A^T y for one view (y of one view).
  void ApplyTranspose(size_t view, const float* y, Vec* accum, float* scratch) const {
    for (size_t b = 0; b < model_.branch_count(); ++b) {
      int k = model_.branch_layers(b)[0];
      const auto& w = model_.weight(b);
      for (size_t i = 0; i < n_; ++i) scratch[i] = w[i % 3] * y[i];
      model_.projection(k).ScatterAdd(view, scratch, (*accum)[k].data());
    }
  }

  // Returns ||A x - l||^2; if gradient is given, it becomes 2 A^T (A x - l).
  double Residual(const Patterns& x, const LightField& l, Vec* gradient) const {
    const size_t views = model_.geometry().view_count();
    std::vector<double> view_sums(views);
    PartSums locals;
#pragma omp parallel
    {
      std::vector<float> r(n_), scratch(n_);
      ForEachPartOfThread(locals.parts(), [&](int p) {
        Vec* local = gradient ? locals.Part(p, x) : nullptr;
        const ItemRange share = StaticShare(views, p, locals.parts());
        for (size_t v = share.begin; v < share.end; ++v) {
          Apply(v, x, r.data(), scratch.data());
          const float* lv = l.view(v);
          double sum = 0;
          for (size_t i = 0; i < n_; ++i) {
            r[i] -= lv[i];
            sum += double(r[i]) * r[i];
            r[i] *= 2.0f;
          }
          view_sums[v] = sum;
          if (gradient) ApplyTranspose(v, r.data(), local, scratch.data());
        }
      });
    }
    double total = 0;
    for (double s : view_sums) total += s;  // in view order
    if (gradient) locals.SumInPartOrder(x, gradient);
    return SumAcrossRanks(gradient, nullptr, total);
  }

  // H p = 2 A^T A p, restricted to `free` entries; returns p^T H p.
  double Hessian(const Vec& p, const Vec& free, Vec* hp, const Patterns& shape) const {
    Patterns pf = shape;
    for (size_t k = 0; k < p.size(); ++k)
      for (size_t i = 0; i < p[k].size(); ++i) pf[k].rgb[i] = static_cast<float>(p[k][i]);
    const size_t views = model_.geometry().view_count();
    PartSums locals;
#pragma omp parallel
    {
      std::vector<float> ap(n_), scratch(n_);
      ForEachPartOfThread(locals.parts(), [&](int part) {
        Vec* local = locals.Part(part, shape);
        const ItemRange share = StaticShare(views, part, locals.parts());
        for (size_t v = share.begin; v < share.end; ++v) {
          Apply(v, pf, ap.data(), scratch.data());
          for (size_t i = 0; i < n_; ++i) ap[i] *= 2.0f;
          ApplyTranspose(v, ap.data(), local, scratch.data());
        }
      });
    }
    locals.SumInPartOrder(shape, hp);
    SumAcrossRanks(hp, nullptr, 0.0);
    for (size_t k = 0; k < hp->size(); ++k)
      for (size_t i = 0; i < (*hp)[k].size(); ++i) (*hp)[k][i] *= free[k][i];
    return Dot(p, *hp);
  }

 private:
  const DisplayModel& model_;
  size_t n_;
};

// The same interface from the normal matrix: f = x^T G x - 2 x^T A^T l + ||l||^2.
class GramOperator {
 public:
  GramOperator(const DisplayModel& model, const AdditiveOperator& rays, const LightField& l, const Patterns& shape)
      : gram_(model) {
    Patterns zero = shape;
    for (LayerPattern& p : zero) std::fill(p.rgb.begin(), p.rgb.end(), 0.0f);
    Vec g0;
    squared_target_ = rays.Residual(zero, l, &g0);  // ||l||^2 and -2 A^T l
    target_ = std::move(g0);
    for (auto& block : target_)
      for (double& v : block) v *= -0.5;
  }

  double Residual(const Patterns& x, const LightField&, Vec* gradient) const {
    Vec xv = Zeros(x), gx;
    for (size_t k = 0; k < x.size(); ++k)
      for (size_t i = 0; i < x[k].rgb.size(); ++i) xv[k][i] = x[k].rgb[i];
    gram_.Apply(xv, &gx);
    SumAcrossRanks(&gx, nullptr, 0.0);  // the Gram of every rank's views
    // Cancellation leaves round-off of about 1e-16 ||l||^2: clamp it at a perfect fit.
    const double f = std::max(0.0, Dot(xv, gx) - 2 * Dot(target_, xv) + squared_target_);
    if (gradient) {
      *gradient = std::move(gx);
      Axpy(-1.0, target_, gradient);
      for (auto& block : *gradient)
        for (double& v : block) v *= 2.0;
    }
    return f;
  }

  double Hessian(const Vec& p, const Vec& free, Vec* hp, const Patterns&) const {
    gram_.Apply(p, hp);
    SumAcrossRanks(hp, nullptr, 0.0);
    for (size_t k = 0; k < hp->size(); ++k)
      for (size_t i = 0; i < (*hp)[k].size(); ++i) (*hp)[k][i] *= 2.0 * free[k][i];
    return Dot(p, *hp);
  }

 private:
  AdditiveGram gram_;
  Vec target_;  // A^T l
  double squared_target_ = 0;
};

std::string Unsuitable(const DisplaySystem& system) {
  for (const Branch& b : system.branches)
    if (b.layers.size() != 1)
      return "needs one layer per branch; branch \"" + b.name + "\" stacks " + std::to_string(b.layers.size()) +
             " (use hybrid)";
  return "";
}

// Variables pressed against a bound by the gradient stay there this step: 0 where held, else 1.
Vec FreeVariables(const Patterns& t, const Vec& g) {
  Vec free = Zeros(t);
  for (size_t k = 0; k < t.size(); ++k)
    for (size_t i = 0; i < free[k].size(); ++i) {
      float x = t[k].rgb[i];
      bool held = (x <= 0.0f && g[k][i] > 0) || (x >= 1.0f && g[k][i] < 0);
      free[k][i] = held ? 0.0 : 1.0;
    }
  return free;
}

// Steihaug CG on the free variables from the projected gradient `residual`
// (of norm gnorm), bounded by the trust radius: the step d.
template <class Operator>
Vec SteihaugStep(const Operator& A, const Patterns& t, const Vec& free, Vec residual, double gnorm, double radius) {
  constexpr int kMaxCg = 25;
  Vec d = Zeros(t), p = residual, hp;
  double rr = gnorm * gnorm;
  for (int j = 0; j < kMaxCg; ++j) {
    double curvature = A.Hessian(p, free, &hp, t);
    double dd = Dot(d, d), dp = Dot(d, p), pp = Dot(p, p);
    auto to_boundary = [&] {
      double tau = (-dp + std::sqrt(dp * dp + pp * (radius * radius - dd))) / pp;
      Axpy(tau, p, &d);
    };
    if (curvature <= 0) {
      to_boundary();
      break;
    }
    double alpha = rr / curvature;
    if (dd + 2 * alpha * dp + alpha * alpha * pp >= radius * radius) {
      to_boundary();
      break;
    }
    Axpy(alpha, p, &d);
    Axpy(-alpha, hp, &residual);
    double rr_next = Dot(residual, residual);
    if (std::sqrt(rr_next) <= 1e-2 * gnorm) break;
    for (size_t k = 0; k < p.size(); ++k)
      for (size_t i = 0; i < p[k].size(); ++i) p[k][i] = residual[k][i] + (rr_next / rr) * p[k][i];
    rr = rr_next;
  }
  return d;
}

// The projected backtracking search along d from t (objective f, gradient g).
struct SearchResult {
  Patterns trial;
  double step = 1.0, predicted = 0;  // the step taken (halved on each try), the first try's decrease
  bool accepted = false;
};

template <class Operator>
SearchResult ProjectedSearch(const Operator& A, const LightField& l, const Patterns& t, const Vec& d, const Vec& g,
                             double f) {
  SearchResult r{t};
  double f_trial = f, decrease = 0;
  // Leaves the loop by break when accepted, so that `step` is the accepted one (the increment would halve it).
  for (int tries = 0; tries < 20; ++tries, r.step *= 0.5) {
    decrease = 0;
    for (size_t k = 0; k < t.size(); ++k)
      for (size_t i = 0; i < d[k].size(); ++i) {
        double x = std::clamp(double(t[k].rgb[i]) + r.step * d[k][i], 0.0, 1.0);
        r.trial[k].rgb[i] = static_cast<float>(x);
        decrease += g[k][i] * (double(r.trial[k].rgb[i]) - t[k].rgb[i]);
      }
    f_trial = A.Residual(r.trial, l, nullptr);
    r.accepted = f_trial <= f + 1e-4 * decrease;
    if (tries == 0) r.predicted = decrease;
    if (r.accepted) break;
  }
  return r;
}

class AdditiveTrustRegionSolver final : public Solver {
 public:
  SolverReport Solve(const DisplayModel& model, const LightField& target, const SolverOptions& options,
                     Patterns* t) const override {
    SolveLoop loop("additive-trust-region", model, target, options, t);
    const std::string why = Unsuitable(model.system());
    if (!loop.Start(why.empty() ? why : "additive-trust-region " + why)) return loop.Finish();
    const LightField& l = loop.target();
    AdditiveOperator rays(model);
    if (AdditiveGram::Applicable(model)) {
      GramOperator gram(model, rays, l, *t);
      Run(gram, l, &loop, t);
    } else {
      Run(rays, l, &loop, t);
    }
    return loop.Finish();
  }

 private:
  template <class Operator>
  static void Run(const Operator& A, const LightField& l, SolveLoop* loop_pointer, Patterns* t) {
    SolveLoop& loop = *loop_pointer;
    Vec g;
    double f = A.Residual(*t, l, &g);
    const double start_objective = f;
    double radius = loop.ResumedState("radius", -1);
    do {
      const Vec free = FreeVariables(*t, g);
      Vec residual = Zeros(*t);
      for (size_t k = 0; k < g.size(); ++k)
        for (size_t i = 0; i < g[k].size(); ++i) residual[k][i] = -g[k][i] * free[k][i];
      double gnorm = std::sqrt(Dot(residual, residual));
      if (gnorm == 0) break;  // stationary: the projected gradient vanishes
      if (radius < 0) radius = gnorm;
      const Vec d = SteihaugStep(A, *t, free, std::move(residual), gnorm, radius);
      SearchResult search = ProjectedSearch(A, l, *t, d, g, f);
      if (!search.accepted) {
        // At the optimum only round-off is left to decrease: the objective is a
        // float-gathered sum on the ray path (relative noise about 1e-7), and a
        // difference of terms of the size of ||l||^2 in layer space.
        if (f <= 1e-12 * start_objective || -search.predicted <= 1e-6 * f)
          loop.Converge("no decrease is left above round-off");
        else
          loop.Fail("the projected search found no decrease (objective " + std::to_string(f) + ")");
        break;
      }
      double dnorm = std::sqrt(Dot(d, d));
      const double step = search.step;
      radius = step < 1.0 ? std::max(0.25 * radius, step * dnorm) : std::max(radius, 2.0 * dnorm);
      *t = std::move(search.trial);
      f = A.Residual(*t, l, &g);
      loop.SetState("radius", radius);
    } while (loop.EndIteration(f));
  }
};

}  // namespace

SolverType AdditiveTrustRegionSolverType() {
  SolverOptions defaults;
  defaults.iterations = 200;
  defaults.tolerance = 1e-6;
  SolverType type(
      "additive-trust-region",
      "box-constrained least squares of an additive display by a matrix-free projected trust-region "
      "Newton-CG method",
      [] { return std::make_unique<AdditiveTrustRegionSolver>(); }, defaults);
  type.unsuitable = Unsuitable;
  type.default_rank = 2;
  type.memory.passes = kSynthesisPass;  // the objective; its own Gram system otherwise
  return type;
}

}  // namespace layerlab
