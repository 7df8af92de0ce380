// A moving target solved frame by frame (`layerlab solve --frames N`): frame
// k is the target scene at k / frame rate (targets/target_motion.h), rendered
// and factorized. The first frame is solved cold with the scene's settings;
// each later one begins from the frame before and runs a few iterations, as a
// display showing video would. Each frame's row gives what it cost and how
// far it falls short of a cold solve of the same frame.
#pragma once

#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "layerlab/analysis/solve_job.h"
#include "layerlab/targets/target_scene.h"

namespace layerlab {

struct FrameSequenceOptions {
  int frames = 0;            // frames to solve, the first at time 0
  int frame_iterations = 3;  // iterations of each frame after the first
  // A cold solve (the scene's settings, from the usual first guess) of every k-th frame after the first, whose
  // PSNR is the frame's reference; 0: none (the sequence then costs only its own solves).
  int cold_every = 1;
};

struct FrameRow {
  static constexpr double kNone = std::numeric_limits<double>::quiet_NaN();
  int frame = 0;
  double time_s = 0;          // s, in the scene's animation
  double render_seconds = 0;  // the frame's target
  double solve_seconds = 0;   // the frame's factorization, setup included
  int iterations = 0;
  double psnr_db = kNone;
  double cold_psnr_db = kNone, cold_seconds = kNone;  // the frame solved cold (when it has a reference)
  // Per layer: the RMS change of its pattern (linear transmittance, every pixel and channel) from the frame
  // before; 0 for the first frame.
  std::vector<double> layer_change;
};

struct FrameSequence {
  std::vector<FrameRow> rows;
  std::vector<std::string> layer_names;
  SolvedJob last;  // the last frame's solution
};

// Refuses what a sequence cannot be: a count below 1, a scene that does not move, the retinal objective.
void RequireFrameSequence(const SolveJob& job, const TargetScene& scene, const FrameSequenceOptions& options);

// Solves `options.frames` frames of `scene` (which must move) with `job`'s display and solver. `on_frame` is
// called after each frame. A failed solve ends the sequence with an Error naming the frame.
FrameSequence SolveFrameSequence(const SolveJob& job, const TargetScene& scene, const FrameSequenceOptions& options,
                                 const std::function<void(const FrameRow&)>& on_frame = {});

// frames.csv: one row per frame, units in the column names.
void WriteFramesCsv(const FrameSequence& sequence, const std::string& path);
// The sequence in a few lines: the first frame, then the warm frames' factorization rate, PSNR against the
// cold solves, render time, and each layer's change between frames.
std::string FramesSummary(const FrameSequence& sequence, const FrameSequenceOptions& options, const TargetScene& scene);

}  // namespace layerlab
