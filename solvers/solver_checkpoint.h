// What a solve needs to continue where it stopped: the patterns after an
// iteration, the iteration count, the trace so far, and the few numbers a
// solver carries between iterations (the joint solver's step exponent, the
// trust region's radius). Patterns are stored as float EXR, so a resumed
// solve continues bit for bit.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "solvers/solver.h"

namespace layerlab {

struct SolverCheckpoint {
  std::string solver;
  int iteration = 0;
  double seconds = 0;  // wall time spent before the checkpoint
  Patterns patterns;
  std::map<std::string, double> state;
  std::vector<IterationRecord> trace;
};

// Into `folder` (created): one EXR per layer named by the iteration, then
// checkpoint.json, each atomically; the previous checkpoint's files are
// removed only after the new one is complete.
void WriteCheckpoint(const DisplayModel& model, const SolverCheckpoint& checkpoint, const std::string& folder);
// Reads folder/checkpoint.json and its patterns; checks they fit `model`.
SolverCheckpoint ReadCheckpoint(const DisplayModel& model, const std::string& folder);

}  // namespace layerlab
