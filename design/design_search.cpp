#include "layerlab/design/design_search.h"

#include <nlopt.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <limits>
#include <map>
#include <memory>

#include "layerlab/design/design_gradient.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/interrupt.h"
#include "layerlab/framework/units.h"

namespace layerlab {
namespace {

using Clock = std::chrono::steady_clock;

struct OptDeleter {
  void operator()(nlopt_opt o) const { nlopt_destroy(o); }
};
using Opt = std::unique_ptr<std::remove_pointer_t<nlopt_opt>, OptDeleter>;

double Dot(const std::vector<double>& a, const double* x) {
  double s = 0;
  for (size_t i = 0; i < a.size(); ++i) s += a[i] * x[i];
  return s;
}

double Scale(const DesignConstraint& c) {
  return std::max({1.0, c.min ? std::abs(*c.min) : 0.0, c.max ? std::abs(*c.max) : 0.0});
}

// What the search and the report count as meeting a constraint: within 1e-9 of its bound's scale.
constexpr double kConstraintSlack = 1e-9;
bool Violates(const DesignConstraint& c, double violation) { return violation > kConstraintSlack * Scale(c); }

std::string Bound(const DesignConstraint& c, double v) {
  return FormatGeneral(v) + (c.unit.empty() || c.unit == "1" ? "" : " " + c.unit);
}

// --- feasibility of the linear constraints, before any evaluation ---

// The least t with every linear constraint violated by at most t, over the bounds; x at that t.
double LeastViolation(const DesignSpec& spec, const std::vector<const DesignConstraint*>& linear,
                      std::vector<double>* x) {
  const size_t n = spec.variables.size();
  struct Data {
    const DesignConstraint* c;
    bool upper;
  };
  std::vector<Data> rows;
  for (const DesignConstraint* c : linear) {
    if (c->min) rows.push_back({c, false});
    if (c->max) rows.push_back({c, true});
  }
  Opt opt(nlopt_create(NLOPT_LN_COBYLA, static_cast<unsigned>(n + 1)));
  std::vector<double> lo(n + 1), hi(n + 1), z(n + 1), tol(n + 1);
  double span = 0;
  for (size_t k = 0; k < n; ++k) {
    lo[k] = spec.variables[k].min;
    hi[k] = spec.variables[k].max;
    z[k] = 0.5 * (lo[k] + hi[k]);
    tol[k] = 1e-9 * (hi[k] - lo[k]);
    for (const Data& r : rows) span = std::max(span, std::abs(r.c->coefficients[k]) * (hi[k] - lo[k]));
  }
  lo[n] = 0;
  hi[n] = HUGE_VAL;
  z[n] = 0;
  for (const Data& r : rows) {
    const double v = Dot(r.c->coefficients, z.data());
    z[n] = std::max(z[n], r.upper ? v - *r.c->max : *r.c->min - v);
  }
  tol[n] = 1e-12 * std::max(span, 1.0);
  nlopt_set_lower_bounds(opt.get(), lo.data());
  nlopt_set_upper_bounds(opt.get(), hi.data());
  nlopt_set_min_objective(
      opt.get(), [](unsigned m, const double* v, double*, void*) { return v[m - 1]; }, nullptr);
  for (Data& r : rows)
    nlopt_add_inequality_constraint(
        opt.get(),
        [](unsigned m, const double* v, double*, void* data) {
          const Data& d = *static_cast<Data*>(data);
          const double a = Dot(d.c->coefficients, v);
          return (d.upper ? a - *d.c->max : *d.c->min - a) - v[m - 1];
        },
        &r, 0.0);
  nlopt_set_xtol_abs(opt.get(), tol.data());
  nlopt_set_maxeval(opt.get(), 20000);
  double t = 0;
  nlopt_optimize(opt.get(), z.data(), &t);  // whatever it returns, the violation is measured below
  x->assign(z.begin(), z.begin() + static_cast<long>(n));
  double worst = 0;
  for (const DesignConstraint* c : linear) worst = std::max(worst, ConstraintViolation(*c, *x, nullptr));
  return worst;
}

// --- the search ---

struct Search {
  const DesignSpec* spec = nullptr;
  DesignEvaluator* evaluator = nullptr;
  nlopt_opt outer = nullptr;  // the optimizer the callbacks stop
  std::exception_ptr error;
  std::string stopped;
  Clock::time_point start;
  size_t budget_base = 0;                                            // designs asked before this search began
  int budget = 0;                                                    // the search's evaluations
  std::map<const DesignEvaluation*, std::vector<double>> gradients;  // of the loss, for a gradient search
  size_t stage_limit = 0;  // the designs asked at which the running stage ends
  bool stage_done = false;

  bool OverBudget() {
    if (evaluator->asked() >= stage_limit) stage_done = true;
    if (evaluator->asked() - budget_base >= static_cast<size_t>(budget)) {
      stopped = "the budget of " + std::to_string(budget) + " evaluations was spent";
      return true;
    }
    if (spec->optimizer.seconds &&
        std::chrono::duration<double>(Clock::now() - start).count() >= *spec->optimizer.seconds) {
      stopped = "the budget of " + FormatGeneral(*spec->optimizer.seconds) + " s was spent";
      return true;
    }
    return false;
  }

  // The evaluation at x, or nothing once the search must stop (the budget, an error, an interrupt).
  const DesignEvaluation* At(const double* x) {
    if (error || !stopped.empty() || stage_done) {
      nlopt_force_stop(outer);
      return nullptr;
    }
    const std::vector<double> point(x, x + spec->variables.size());
    try {
      if (Interrupted()) throw InterruptedError("optimize: interrupted");
      if (OverBudget() || stage_done) {
        // A design already evaluated costs nothing: the budget stops only a new one.
        for (const DesignEvaluation* e : evaluator->asked_in_order())
          if (e->x == point) return e;
        nlopt_force_stop(outer);
        return nullptr;
      }
      return &evaluator->Evaluate(point);
    } catch (...) {
      error = std::current_exception();
      nlopt_force_stop(outer);
      return nullptr;
    }
  }
};

struct ConstraintData {
  Search* search;
  const DesignConstraint* c;
  bool upper;
};

// How far x lies outside the linear constraints, each violation relative to its bound's scale; 0 inside.
double LinearViolation(const DesignSpec& spec, const double* x) {
  const std::vector<double> point(x, x + spec.variables.size());
  double sum = 0;
  for (const DesignConstraint& c : spec.constraints)
    if (!c.metric)
      if (const double v = ConstraintViolation(c, point, nullptr); Violates(c, v)) sum += v / Scale(c);
  return sum;
}

// The gradient of LinearViolation where it is positive.
void LinearViolationGradient(const DesignSpec& spec, const double* x, double* grad) {
  const std::vector<double> point(x, x + spec.variables.size());
  for (const DesignConstraint& c : spec.constraints) {
    if (c.metric || !Violates(c, ConstraintViolation(c, point, nullptr))) continue;
    const double sign = c.min && *c.min - Dot(c.coefficients, x) > 0 ? -1.0 : 1.0;
    for (size_t k = 0; k < point.size(); ++k) grad[k] += sign * c.coefficients[k] / Scale(c);
  }
}

double Objective(unsigned n, const double* x, double* grad, void* data) {
  Search& s = *static_cast<Search*>(data);
  if (grad) std::fill(grad, grad + n, 0.0);
  // A design outside the linear constraints is known to be infeasible without a run (and a
  // global stage proposes many): it costs no evaluation, and is worse than any that ran.
  if (const double v = LinearViolation(*s.spec, x); v > 0) {
    if (s.error || !s.stopped.empty() || s.stage_done) nlopt_force_stop(s.outer);
    if (grad) {
      LinearViolationGradient(*s.spec, x, grad);
      for (unsigned k = 0; k < n; ++k) grad[k] *= 10;
    }
    return s.evaluator->FailedLoss() + 10 * v;
  }
  const DesignEvaluation* e = s.At(x);
  if (!e) return HUGE_VAL;  // the search is stopping: no value, and none that could pass for a design's
  if (grad && e->failed) {  // no slope to follow: a zero gradient would read as converged
    s.stopped = "evaluation " + e->id + " failed (" + e->error + "), and a gradient search has no slope there";
    nlopt_force_stop(s.outer);
    return s.evaluator->FailedLoss();
  }
  if (grad) {
    auto it = s.gradients.find(e);
    if (it == s.gradients.end()) {
      try {
        // The loss is weight x (-psnr) (GradientProblem: a single psnr term).
        std::vector<double> g = PsnrGradient(*s.spec, *s.evaluator, *e);
        for (double& v : g) v *= -s.spec->objective[0].weight;
        it = s.gradients.emplace(e, std::move(g)).first;
      } catch (...) {
        s.error = std::current_exception();
        nlopt_force_stop(s.outer);
        return HUGE_VAL;
      }
    }
    std::copy(it->second.begin(), it->second.end(), grad);
  }
  return e->failed ? s.evaluator->FailedLoss() : e->loss;
}

double Constraint(unsigned n, const double* x, double* grad, void* data) {
  const ConstraintData& d = *static_cast<ConstraintData*>(data);
  if (grad)  // a gradient search has linear constraints only (GradientProblem)
    for (unsigned k = 0; k < n; ++k) grad[k] = d.c->metric ? 0.0 : (d.upper ? 1.0 : -1.0) * d.c->coefficients[k];
  double value = 0;
  if (d.c->metric) {
    // Outside the linear constraints a design is not run: it meets no constraint on its metrics.
    if (LinearViolation(*d.search->spec, x) > 0) return 1;
    const DesignEvaluation* e = d.search->At(x);
    if (!e) return HUGE_VAL;
    if (e->failed) return 1e3;  // a design that does not run meets no constraint on its metrics
    value = e->metrics[*d.c->metric];
  } else {
    value = Dot(d.c->coefficients, x);
  }
  return d.upper ? value - *d.c->max : *d.c->min - value;
}

nlopt_algorithm LocalAlgorithm(const std::string& name) {
  if (name == "bobyqa") return NLOPT_LN_BOBYQA;
  if (name == "nelder-mead") return NLOPT_LN_NELDERMEAD;
  if (name == "slsqp") return NLOPT_LD_SLSQP;
  return NLOPT_LN_COBYLA;
}

Opt Create(nlopt_algorithm a, const DesignSpec& spec) {
  const unsigned n = static_cast<unsigned>(spec.variables.size());
  Opt opt(nlopt_create(a, n));
  if (!opt) throw Error("optimize: NLopt could not create its optimizer");
  std::vector<double> lo(n), hi(n), tol(n), step(n);
  for (unsigned k = 0; k < n; ++k) {
    lo[k] = spec.variables[k].min;
    hi[k] = spec.variables[k].max;
    tol[k] = spec.variables[k].tolerance;
    step[k] = (hi[k] - lo[k]) / 8;
  }
  nlopt_set_lower_bounds(opt.get(), lo.data());
  nlopt_set_upper_bounds(opt.get(), hi.data());
  nlopt_set_xtol_abs(opt.get(), tol.data());
  nlopt_set_initial_step(opt.get(), step.data());
  return opt;
}

std::string Why(nlopt_result r, const Search& s) {
  if (!s.stopped.empty()) return s.stopped;
  switch (r) {
    case NLOPT_XTOL_REACHED:
      return "its step fell below the variables' tolerances";
    case NLOPT_FTOL_REACHED:
      return "the objective stopped improving";
    case NLOPT_MAXEVAL_REACHED:
      return "NLopt's limit of calls (100 x the stage's evaluations, most outside the linear constraints) was reached";
    case NLOPT_MAXTIME_REACHED:
      return "its time budget was spent";
    case NLOPT_ROUNDOFF_LIMITED:
      return "round-off limited its progress";
    case NLOPT_SUCCESS:
    case NLOPT_STOPVAL_REACHED:
      return "it converged";
    default:
      return std::string("NLopt stopped: ") + nlopt_result_to_string(r);
  }
}

// One stage: `algorithm` from x (updated to the stage's best), with the
// constraints directly (COBYLA) or through the augmented Lagrangian.
std::string RunStage(Search* s, nlopt_algorithm algorithm, std::optional<nlopt_algorithm> local, int evaluations,
                     std::vector<double>* x) {
  const DesignSpec& spec = *s->spec;
  Opt stage = Create(algorithm, spec);
  if (algorithm == NLOPT_GN_CRS2_LM) {  // NLopt's 10 (n + 1) would take the stage's whole budget at random
    const size_t n = spec.variables.size();
    nlopt_set_population(
        stage.get(), static_cast<unsigned>(std::max<size_t>(n + 2, std::min<size_t>(10 * (n + 1), evaluations / 3))));
  }
  if (local) {
    Opt inner = Create(*local, spec);
    nlopt_set_local_optimizer(stage.get(), inner.get());  // copied
  }
  Opt outer;
  nlopt_opt target = stage.get();
  const bool direct = algorithm == NLOPT_LN_COBYLA || algorithm == NLOPT_LD_SLSQP;
  if (!spec.constraints.empty() && !direct) {
    outer = Create(NLOPT_AUGLAG, spec);
    nlopt_set_local_optimizer(outer.get(), stage.get());
    target = outer.get();
  }
  std::vector<ConstraintData> data;
  data.reserve(2 * spec.constraints.size());
  for (const DesignConstraint& c : spec.constraints) {
    if (c.min) data.push_back({s, &c, false});
    if (c.max) data.push_back({s, &c, true});
  }
  for (ConstraintData& d : data) nlopt_add_inequality_constraint(target, Constraint, &d, 0.0);
  nlopt_set_min_objective(target, Objective, s);
  // The budget counts evaluations (Search::OverBudget); NLopt's count includes the designs outside
  // the linear constraints, which cost none: a bound on those only.
  nlopt_set_maxeval(target, 100 * std::max(1, evaluations));
  s->outer = target;
  s->stage_limit = s->evaluator->asked() + static_cast<size_t>(std::max(1, evaluations));
  s->stage_done = false;
  double f = 0;
  const nlopt_result r = nlopt_optimize(target, x->data(), &f);
  if (s->error) std::rethrow_exception(s->error);
  if (s->stage_done && s->stopped.empty()) return "the stage's share of the budget was spent";
  return Why(r, *s);
}

}  // namespace

double ConstraintViolation(const DesignConstraint& c, const std::vector<double>& x, const DesignEvaluation* e) {
  double v = 0;
  if (c.metric) {
    if (!e || e->failed) return std::numeric_limits<double>::infinity();
    v = e->metrics[*c.metric];
  } else {
    v = Dot(c.coefficients, x.data());
  }
  double over = 0;
  if (c.min) over = std::max(over, *c.min - v);
  if (c.max) over = std::max(over, v - *c.max);
  return over;
}

bool MeetsLinearConstraints(const DesignSpec& spec, const std::vector<double>& x) {
  return LinearViolation(spec, x.data()) == 0;
}

bool MeetsConstraints(const DesignSpec& spec, const DesignEvaluation& e) {
  if (e.failed) return false;
  for (const DesignConstraint& c : spec.constraints)
    if (Violates(c, ConstraintViolation(c, e.x, &e))) return false;
  return true;
}

const DesignEvaluation* BestFeasible(const DesignSpec& spec, const std::vector<const DesignEvaluation*>& among) {
  const DesignEvaluation* best = nullptr;
  for (const DesignEvaluation* e : among)
    if (MeetsConstraints(spec, *e) &&
        (!best || e->loss < best->loss || (e->loss == best->loss && e->index < best->index)))
      best = e;
  return best;
}

const DesignEvaluation* BestFeasible(const DesignSpec& spec, const DesignEvaluator& evaluator) {
  return BestFeasible(spec, evaluator.evaluations());
}

std::vector<std::string> UnmetConstraints(const DesignSpec& spec, const std::vector<const DesignEvaluation*>& among) {
  // The evaluation that comes closest: the least sum of relative violations.
  const DesignEvaluation* closest = nullptr;
  double least = INFINITY;
  for (const DesignEvaluation* e : among) {
    if (e->failed) continue;
    double sum = 0;
    for (const DesignConstraint& c : spec.constraints) sum += ConstraintViolation(c, e->x, e) / Scale(c);
    if (sum < least) least = sum, closest = e;
  }
  std::vector<std::string> unmet;
  for (const DesignConstraint& c : spec.constraints)
    if (!closest || Violates(c, ConstraintViolation(c, closest->x, closest))) unmet.push_back(c.name);
  return unmet;
}

namespace {

void CheckTogether(const DesignSpec& spec, const std::vector<const DesignConstraint*>& linear) {
  std::vector<double> x;
  const double t = LeastViolation(spec, linear, &x);
  double scale = 1;
  for (const DesignConstraint* c : linear) scale = std::max(scale, Scale(*c));
  if (t <= 1e-7 * scale) return;
  std::string names, first;
  for (size_t i = 0; i < spec.constraints.size(); ++i) {
    const DesignConstraint& c = spec.constraints[i];
    if (c.metric || ConstraintViolation(c, x, nullptr) < 0.5 * t) continue;
    names += (names.empty() ? "\"" : ", \"") + c.name + "\"";
    if (first.empty()) first = "/constraints/" + std::to_string(i);
  }
  throw Error(Location{spec.file, first}, "no design meets the constraints " + names +
                                              " together: within the variables' bounds the design "
                                              "closest to meeting them still misses each by " +
                                              FormatGeneral(t));
}

}  // namespace

void CheckDesignFeasible(const DesignSpec& spec) {
  std::vector<const DesignConstraint*> linear;
  for (size_t i = 0; i < spec.constraints.size(); ++i) {
    const DesignConstraint& c = spec.constraints[i];
    if (c.metric) continue;
    double lo = 0, hi = 0;
    for (size_t k = 0; k < spec.variables.size(); ++k) {
      const double a = c.coefficients[k] * spec.variables[k].min, b = c.coefficients[k] * spec.variables[k].max;
      lo += std::min(a, b);
      hi += std::max(a, b);
    }
    const Location at{spec.file, "/constraints/" + std::to_string(i)};
    const double slack = 1e-12 * std::max({1.0, std::abs(lo), std::abs(hi)});
    if (c.min && *c.min > hi + slack)
      throw Error(at, "no design meets \"" + c.name + "\": " + c.what + " must be at least " + Bound(c, *c.min) +
                          ", but within the variables' bounds it is at most " + Bound(c, hi));
    if (c.max && *c.max < lo - slack)
      throw Error(at, "no design meets \"" + c.name + "\": " + c.what + " must be at most " + Bound(c, *c.max) +
                          ", but within the variables' bounds it is at least " + Bound(c, lo));
    linear.push_back(&c);
  }
  // The start is the first evaluation and the report's reference: it must be a design that runs. A
  // start that meets them all shows the constraints can be met together.
  std::vector<double> start;
  for (const DesignVariable& v : spec.variables) start.push_back(v.start);
  for (size_t i = 0; i < spec.constraints.size(); ++i) {
    const DesignConstraint& c = spec.constraints[i];
    if (c.metric || !Violates(c, ConstraintViolation(c, start, nullptr))) continue;
    if (linear.size() >= 2) CheckTogether(spec, linear);  // no design at all: the better message
    std::string values;
    for (size_t k = 0; k < spec.variables.size(); ++k)
      values += (k ? ", " : "") + spec.variables[k].name + " " + FormatGeneral(start[k]) +
                (spec.variables[k].unit.empty() ? "" : " " + spec.variables[k].unit);
    throw Error(
        Location{spec.file, "/constraints/" + std::to_string(i)},
        "the start (" + values + ") does not meet \"" + c.name + "\": give the variables a \"start\" that does");
  }
}

DesignSearch SearchDesign(const DesignSpec& spec, DesignEvaluator* evaluator) {
  if (spec.optimizer.global == "multistart")
    throw Error("internal error: SearchDesign on a multistart; each start is a SearchFromStart");
  std::vector<double> x;
  for (const DesignVariable& v : spec.variables) x.push_back(v.start);
  return SearchFromStart(spec, x, spec.optimizer.evaluations, evaluator);
}

DesignSearch SearchFromStart(const DesignSpec& spec, std::vector<double> x, int budget, DesignEvaluator* evaluator) {
  Search s;
  s.spec = &spec;
  s.evaluator = evaluator;
  s.start = Clock::now();
  s.budget_base = evaluator->asked();
  s.budget = budget;
  nlopt_srand(spec.optimizer.seed);
  // The start is always evaluated first: the report compares the optimum with it.
  s.stage_limit = evaluator->asked() + 1;
  Objective(static_cast<unsigned>(x.size()), x.data(), nullptr, &s);
  if (s.error) std::rethrow_exception(s.error);
  const nlopt_algorithm local = LocalAlgorithm(spec.optimizer.local);
  DesignSearch result;
  if (spec.optimizer.global == "mlsl") {
    result.stopped = RunStage(&s, NLOPT_G_MLSL_LDS, local, budget - 1, &x);
  } else {
    if (spec.optimizer.global == "crs") {
      result.stopped = RunStage(&s, NLOPT_GN_CRS2_LM, std::nullopt, std::max(1, 2 * (budget - 1) / 3), &x);
      // From the best design this search has seen (not the log's later ones), else from the start.
      x = evaluator->asked_in_order().front()->x;
      if (const DesignEvaluation* best = BestFeasible(spec, evaluator->asked_in_order())) x = best->x;
    }
    if (s.stopped.empty()) result.stopped = RunStage(&s, local, std::nullopt, budget, &x);  // the rest
  }
  result.seconds = std::chrono::duration<double>(Clock::now() - s.start).count();
  return result;
}

}  // namespace layerlab
