// What `layerlab optimize` leaves in DIR besides its evaluations' jobs
// (design/design_evaluator.h), switched into place together
// (framework/staged_output.h):
//
//   best_scene.json  the base scene with the best design's values, ready for `layerlab run`
//   history.csv      every evaluation: its variables, metrics, objective and the best so far, with units
//   convergence.svg  the best objective against evaluations and against evaluation time
//   surface.svg      the objective over the variables, from the evaluations (one or two variables)
//   report.html      the optimized design against the starting one, with links to both runs' reports
#pragma once

#include <string>
#include <vector>

#include "layerlab/design/design_evaluator.h"
#include "layerlab/design/design_search.h"

namespace layerlab {

// What the report is made from: every evaluation (by index; in a multistart
// start by start), and how many this command ran and read back from logs.
struct DesignHistory {
  std::vector<const DesignEvaluation*> evaluations;
  size_t ran = 0, replayed = 0;
};

// The objective as the history shows it: the metric itself for one term, else the weighted sum minimized.
double ShownObjective(const DesignSpec& spec, const DesignEvaluation& e);

// Writes the files above; `best` may be null (no design met the constraints:
// no best_scene.json). `scenes` (any of the run's evaluators) supplies the
// scenes and job folders of the history's designs. Returns the files written,
// relative to `out`.
std::vector<std::string> WriteDesignReport(const DesignSpec& spec, const DesignEvaluator& scenes,
                                           const DesignHistory& history, const DesignSearch& search,
                                           const DesignEvaluation* best, const std::string& out);

}  // namespace layerlab
