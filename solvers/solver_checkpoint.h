// What a solve needs to continue where it stopped: the patterns after an
// iteration, the iteration count, the trace so far, and the few numbers a
// solver carries between iterations (the joint solver's step exponent, the
// trust region's radius). Patterns are stored as float EXR, so a resumed
// solve continues bit for bit.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "layerlab/solvers/solver.h"

namespace layerlab {

struct SolverCheckpoint {
  std::string solver;
  int iteration = 0;
  double seconds = 0;  // wall time spent before the checkpoint
  Patterns patterns;
  std::map<std::string, double> state;
  std::vector<IterationRecord> trace;
};

// What a checkpoint was made for: "display", "target", "solver", "options".
using CheckpointInputs = std::map<std::string, std::string>;

// The digest of a solve's inputs: the compiled display and its sampling, the
// target's geometry and every value of its views, the solver, and the options
// that change the result (not iterations, time budget, tolerance or threads):
// with the retinal objective its states, weights, sample size, target and
// contrast weighting too.
CheckpointInputs CheckpointDigest(const DisplayModel& model, Sampling sampling, const LightField& target,
                                  const std::string& solver, const SolverOptions& options);
// Throws layerlab::Error naming what differs between the digest recorded in
// folder/checkpoint.json and `now`, and that nothing was written.
void RefuseMismatchedCheckpoint(const std::string& folder, const CheckpointInputs& now);

// Into `folder` (created): one EXR per layer named by the iteration, then
// checkpoint.json, each atomically; the previous checkpoint's files are
// removed only after the new one is complete. `inputs` (CheckpointDigest) is
// recorded for RefuseMismatchedCheckpoint.
void WriteCheckpoint(const DisplayModel& model, const SolverCheckpoint& checkpoint, const std::string& folder,
                     const CheckpointInputs& inputs);
// Reads folder/checkpoint.json and its patterns; checks they fit `model`.
SolverCheckpoint ReadCheckpoint(const DisplayModel& model, const std::string& folder);

}  // namespace layerlab
