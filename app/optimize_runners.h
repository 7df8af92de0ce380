// The ways `layerlab optimize` runs a multistart's starts (design/design_starts.h):
// in turn in this process, a process pool on this machine, MPI ranks, or a
// Slurm job array whose scripts it writes. Each start resumes from its own log.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "layerlab/app/sweep_runners.h"
#include "layerlab/design/design_spec.h"

namespace layerlab::app {

// Runs each start as `layerlab optimize DESIGN --out DIR --start K` (plus
// `arguments`), at most `processes` at a time; prints a line per start.
// Returns the starts that failed, with why.
std::vector<std::string> RunStartsLocally(const DesignSpec& spec, const std::string& out,
                                          const std::vector<std::string>& arguments, int processes);

// Under mpirun: start k on rank k mod N, each rank's in turn. Every rank
// returns once all have ended; *is_root says whether this is rank 0, which
// writes the report. Returns (on rank 0) the evaluations the starts' logs held
// before. A rank that throws ends all ranks (MPI_Abort).
size_t RunStartsMpi(const DesignSpec& spec, const std::string& out, bool* is_root);

// The Slurm array of a multistart: task k runs start k, the gather step the report.
SlurmArrayCommand OptimizeArrayCommand(const DesignSpec& spec, const std::vector<std::string>& arguments);

}  // namespace layerlab::app
