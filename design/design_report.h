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

// The objective as the history shows it: the metric itself for one term, else the weighted sum minimized.
double ShownObjective(const DesignSpec& spec, const DesignEvaluation& e);

// Writes the files above; `best` may be null (no design met the constraints:
// no best_scene.json). Returns the files written, relative to `out`.
std::vector<std::string> WriteDesignReport(const DesignSpec& spec, const DesignEvaluator& evaluator,
                                           const DesignSearch& search, const DesignEvaluation* best,
                                           const std::string& out);

}  // namespace layerlab
