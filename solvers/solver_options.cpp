#include <cmath>

#include "layerlab/elements/eye_pose.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/units.h"
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
  if (eyebox_range_m > 0) {
    if (objective != ObjectiveKind::kRetinal && !measure_focal_stack) {
      *error =
          "eyebox_range: weighs pupil positions in the retinal objective, and this solve's objective is "
          "\"lightfield\" (which weighs every view of the eyebox alike); set the objective to \"retinal\"";
      return false;
    }
  } else if (eyebox_sigma_m > 0 && !(eyebox_step_m > 0)) {
    *error = "eyebox_sigma: describes the eyebox grid of eyebox_range, which is 0 (the eye's pupil alone)";
    return false;
  }
  if (std::string grid =
          EyeboxGridViolation(eyebox_range_m, eyebox_step_m, kMaxEyeboxPupils, " (each holds its own retinal tables)");
      !grid.empty()) {
    *error = std::move(grid);
    return false;
  }
  if (!measure_metrics.empty() && objective != ObjectiveKind::kRetinal && !measure_focal_stack) {
    *error = "measure_metrics: scores the focal stack, which this solve does not measure; set measure_focal_stack";
    return false;
  }
  if (objective == ObjectiveKind::kRetinal && !retinal.weights.empty() &&
      retinal.weights.size() != retinal.states_diopters.size())
    return fail("retinal.weights", double(retinal.weights.size()), "must be one per state (retinal.states)");
  return true;
}

std::vector<PupilWeight> EyeboxPupils(const SolverOptions& o) {
  if (EyeboxGridSize(o.eyebox_range_m, o.eyebox_step_m) > kMaxEyeboxPupils)
    throw Error("eyebox_step: makes more than " + std::to_string(kMaxEyeboxPupils) + " pupil positions");
  std::vector<PupilWeight> pupils;
  for (const std::array<double, 2>& offset : EyeboxGridOffsets(o.eyebox_range_m, o.eyebox_step_m)) {
    PupilWeight p{offset[0], offset[1], 1.0};
    if (o.eyebox_sigma_m > 0)
      p.weight = std::exp(-(p.offset_x_m * p.offset_x_m + p.offset_y_m * p.offset_y_m) /
                          (2 * o.eyebox_sigma_m * o.eyebox_sigma_m));
    pupils.push_back(p);
  }
  return pupils;
}

RetinalObjectiveOptions RetinalOptionsOf(const SolverOptions& o) {
  RetinalObjectiveOptions r = o.retinal;
  if (r.pupils.empty()) r.pupils = EyeboxPupils(o);
  return r;
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
