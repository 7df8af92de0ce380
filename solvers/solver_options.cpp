#include "layerlab/solvers/solver.h"
#include "layerlab/solvers/solver_option_table.h"

namespace layerlab {

std::string ToString(TargetRange r) { return r == TargetRange::kClip ? "clip" : "scale"; }
std::string ToString(ObjectiveKind k) { return k == ObjectiveKind::kLightField ? "lightfield" : "retinal"; }
std::optional<ObjectiveKind> ObjectiveKindNamed(const std::string& name) {
  for (ObjectiveKind k : {ObjectiveKind::kLightField, ObjectiveKind::kRetinal})
    if (name == ToString(k)) return k;
  return std::nullopt;
}

// Which keys every solver reads is the registry's; what they mean is the option table's.
const std::vector<SolverOptionKey>& CommonSolverOptionKeys() {
  static const std::vector<SolverOptionKey> keys = [] {
    std::vector<SolverOptionKey> out;
    for (const char* key :
         {"iterations", "time_budget", "tolerance", "initial_value", "seed", "threads", "target_range"})
      out.push_back({key, FindSolverOption(key)->meaning});
    return out;
  }();
  return keys;
}

SolverOptionKey SubIterationsKey() { return {"sub_iterations", FindSolverOption("sub_iterations")->meaning}; }

// The ranges are the option table's; what relates two options is checked here.
bool SolverOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& field, double value, const std::string& constraint) {
    *error = OptionViolation(field, value, constraint);
    return false;
  };
  if (!RangesHold(SolverOptionTable(), *this, error)) return false;
  if (initial_value >= 0 && initial_value < floor)
    return fail("initial_value", initial_value, FindSolverOption("initial_value")->Constraint());
  if (retinal.contrast_sensitivity && objective != ObjectiveKind::kRetinal) {
    *error =
        "contrast_sensitivity: true: weights the retinal objective's residuals, and this solve's objective is "
        "\"lightfield\"; set the objective to \"retinal\" or leave contrast_sensitivity out";
    return false;
  }
  if (objective == ObjectiveKind::kRetinal && !retinal.weights.empty() &&
      retinal.weights.size() != retinal.states_diopters.size())
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
