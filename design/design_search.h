// The search of `layerlab optimize` (design/design_spec.h) with NLopt's
// derivative-free algorithms: a local search (COBYLA, BOBYQA, Nelder-Mead)
// from the start, after an optional global stage (MLSL's multistart from a
// low-discrepancy sequence, or CRS2), within the variables' bounds, the
// linear constraints and the metric constraints (directly for COBYLA, through
// NLopt's augmented Lagrangian for the others), on a budget of evaluations or
// time. Each function value is an evaluation (design/design_evaluator.h).
#pragma once

#include <optional>
#include <string>

#include "layerlab/design/design_evaluator.h"

namespace layerlab {

// Refuses, before anything runs, linear constraints that no design within the
// bounds satisfies: one alone (with the range it can reach), or several
// together (those left violated at the design that violates them least); and
// a start that does not meet one.
// Throws layerlab::Error naming the design file's /constraints/<k>.
void CheckDesignFeasible(const DesignSpec& spec);

// How much design x violates constraint c (0 when it holds), in c's unit;
// `e` supplies a metric constraint's value.
double ConstraintViolation(const DesignConstraint& c, const std::vector<double>& x, const DesignEvaluation* e);

// Whether design x meets every linear constraint (to 1e-9 of its scale): what can be known without a run.
bool MeetsLinearConstraints(const DesignSpec& spec, const std::vector<double>& x);

// Whether evaluation e ran and meets every constraint (to 1e-9 of its scale).
bool MeetsConstraints(const DesignSpec& spec, const DesignEvaluation& e);

// The best evaluation that meets every constraint (to 1e-9 of its scale), or nothing: among
// all the evaluator's, or among `among`.
const DesignEvaluation* BestFeasible(const DesignSpec& spec, const DesignEvaluator& evaluator);
const DesignEvaluation* BestFeasible(const DesignSpec& spec, const std::vector<const DesignEvaluation*>& among);

// The constraints that the evaluation among `among` closest to meeting them all (the
// least sum of relative violations) misses; every constraint when none ran.
std::vector<std::string> UnmetConstraints(const DesignSpec& spec, const std::vector<const DesignEvaluation*>& among);

struct DesignSearch {
  std::string stopped;  // why the search ended, in words
  double seconds = 0;   // its wall time in this process
};

// Runs the optimizer's stages from the design's start on its whole budget; the
// evaluations are the evaluator's. An error or an interrupt inside an
// evaluation ends the search and is rethrown. Not for a multistart.
DesignSearch SearchDesign(const DesignSpec& spec, DesignEvaluator* evaluator);

// The same from design x on `budget` evaluations: one start of a multistart
// (design/design_starts.h) runs the local search alone.
DesignSearch SearchFromStart(const DesignSpec& spec, std::vector<double> x, int budget, DesignEvaluator* evaluator);

}  // namespace layerlab
