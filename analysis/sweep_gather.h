// The gather step of a sweep: every job's row (its job.json) in one table,
// DIR/table.csv and DIR/table.html (units in the headers), and one plot per
// result that varies over the swept parameters, DIR/plots/<result>.svg: the x axis is the
// first numeric parameter, one line per combination of the others. Written
// in a staging folder and switched into place whole (framework/staged_output.h).
#pragma once

#include <string>
#include <vector>

#include "layerlab/analysis/sweep_jobs.h"

namespace layerlab {

struct SweepSummary {
  size_t complete = 0, failed = 0, pending = 0;
  std::vector<std::string> written;  // relative to DIR
};

SweepSummary GatherSweep(const SweepSpec& spec, const std::vector<SweepJob>& jobs, const std::string& out);

}  // namespace layerlab
