// What the scene's "run" section asks for, as read (analysis/run_config.h
// reads it). The keys, units, ranges and defaults of these fields are
// described once, in analysis/run_option_table.h, which also defines IsValid.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "layerlab/analysis/contrast.h"
#include "layerlab/metrics/retinal_metrics.h"
#include "layerlab/solvers/solver.h"

namespace layerlab {

struct FrameSequenceOptions;  // analysis/frame_sequence.h

struct RetinaRunConfig {
  bool enabled = false;
  std::vector<double> accommodation_diopters;  // default: the depths of the display's layers
  std::vector<double> focal_stack_diopters;    // from..to by step; empty when not asked for
  double resolution_deg = 0.05;                // per retinal sample
  double field_x_deg = 0, field_y_deg = 0;     // 0 x 0: the display's field of view
  bool natural = true;                         // natural viewing of the target too
  bool natural_traced = false;                 // traced in the target scene rather than read from its light field
  bool exr_float = false;                      // the images' EXRs in float, not half (RetinaSweepOptions::exr_pixels)
  std::vector<const RetinalMetric*> metrics;   // each state scored against natural viewing by these (empty: PSNR)
  MetricSettings metric_settings;              // their foveal weighting and the JND's exponent
  // Every state in D, sorted, duplicates removed: the slider's positions.
  std::vector<double> states() const;
  // False, with "field: value: constraint" in *error, for a value outside its table range.
  bool IsValid(std::string* error) const;
};

struct ContrastRunConfig {
  bool enabled = false;
  ContrastOptions options;          // accommodation sweep, depths, frequencies, retina
  std::vector<std::string> scenes;  // more displays in the sweep (resolved paths)
  std::string factorized_for;       // the display whose patterns each display also shows (resolved path), or ""
};

struct CompareRunConfig {
  bool enabled = false;
  std::vector<std::string> scenes;            // displays beside this one (resolved paths)
  std::vector<std::string> solvers;           // empty: each scene's own solver
  std::optional<int> iterations;              // unset: each run's own
  std::optional<double> time_budget_s;        // unset: each run's own
  std::vector<ObjectiveKind> objectives;      // empty: each run's own (CompareSelection::objectives)
  std::vector<const RetinalMetric*> metrics;  // empty: PSNR alone (CompareSelection::metrics)
  MetricSettings metric_settings;             // CompareSelection::metric_settings
  bool IsValid(std::string* error) const;
};

struct FramesRunConfig {
  bool enabled = false;
  int count = 0, frame_iterations = 3, cold_every = 1;  // FrameSequenceOptions' frames, frame_iterations, cold_every
  FrameSequenceOptions sequence() const;  // defined with the frames step (analysis/run_frames_section.cpp)
  bool IsValid(std::string* error) const;
};

struct RunConfig {
  RetinaRunConfig retina;
  ContrastRunConfig contrast;
  CompareRunConfig compare;
  FramesRunConfig frames;
  bool write_lightfield = false;           // the synthesized light field of the solve
  bool declared = false;                   // the scene has a "run" section
  bool IsValid(std::string* error) const;  // every section's
};

}  // namespace layerlab
