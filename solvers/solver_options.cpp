#include <cmath>
#include <sstream>

#include "solvers/solver.h"

namespace layerlab {

std::string ToString(TargetRange r) { return r == TargetRange::kClip ? "clip" : "scale"; }
std::string ToString(ObjectiveKind k) { return k == ObjectiveKind::kLightField ? "lightfield" : "retinal"; }
std::optional<ObjectiveKind> ObjectiveKindNamed(const std::string& name) {
  for (ObjectiveKind k : {ObjectiveKind::kLightField, ObjectiveKind::kRetinal})
    if (name == ToString(k)) return k;
  return std::nullopt;
}

const std::vector<SolverOptionKey>& CommonSolverOptionKeys() {
  static const std::vector<SolverOptionKey> keys = {
      {"iterations", "outer iterations"},
      {"time_budget", "wall-clock budget (0: none)"},
      {"tolerance", "stop when the objective changes by less than this, relative (0: never)"},
      {"initial_value", "initial transmittance, or negative for random in [0.25, 0.75]"},
      {"seed", "for random initial patterns"},
      {"threads", "worker threads (0: every core, one per 16384 rays on small problems)"},
      {"target_range", "what to do with target values beyond the display: clip or scale"},
  };
  return keys;
}

SolverOptionKey SubIterationsKey() { return {"sub_iterations", "updates of one multiplicative set before the next"}; }

bool SolverOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& field, double value, const std::string& constraint) {
    std::ostringstream s;
    s << field << ": " << value << ": " << constraint;
    *error = s.str();
    return false;
  };
  if (iterations < 1 || iterations > 1000000) return fail("iterations", iterations, "must be in [1, 1000000]");
  if (sub_iterations < 1 || sub_iterations > 1000)
    return fail("sub_iterations", sub_iterations, "must be in [1, 1000]");
  if (warm_start_iterations < 0 || warm_start_iterations > 1000000)
    return fail("warm_start_iterations", warm_start_iterations, "must be in [0, 1000000]");
  if (!(time_budget >= 0) || !std::isfinite(time_budget))
    return fail("time_budget", time_budget, "must be >= 0 seconds (0 = none)");
  if (!(tolerance >= 0) || !(tolerance < 1)) return fail("tolerance", tolerance, "must be in [0, 1)");
  if (!(initial_value <= 1) || std::isnan(initial_value) || (initial_value >= 0 && initial_value < floor))
    return fail("initial_value", initial_value, "must be in [floor, 1], or negative for random");
  if (threads < 0 || threads > 1024) return fail("threads", threads, "must be in [0, 1024] (0 = all cores)");
  if (!(epsilon > 0) || !(epsilon < 1e-3)) return fail("epsilon", epsilon, "must be in (0, 1e-3)");
  if (!(floor > 0) || !(floor < 0.1))
    return fail("floor", floor, "must be in (0, 0.1): a zero transmittance never recovers");
  if (retinal.contrast_sensitivity && objective != ObjectiveKind::kRetinal) {
    *error =
        "contrast_sensitivity: true: weights the retinal objective's residuals, and this solve's objective is "
        "\"lightfield\"; set the objective to \"retinal\" or leave contrast_sensitivity out";
    return false;
  }
  if (objective == ObjectiveKind::kRetinal && !retinal.weights.empty() &&
      retinal.weights.size() != retinal.states.size())
    return fail("retinal.weights", double(retinal.weights.size()), "must be one per state (retinal.states)");
  return true;
}

std::string ToString(Termination t) {
  switch (t) {
    case Termination::kNotRun:
      return "not run";
    case Termination::kIterationLimit:
      return "iteration limit";
    case Termination::kTimeBudget:
      return "time budget";
    case Termination::kConverged:
      return "converged";
    case Termination::kInterrupted:
      return "interrupted";
    case Termination::kInvalidOptions:
      return "invalid options";
    case Termination::kFailed:
      return "failed";
  }
  return "unknown";
}

}  // namespace layerlab
