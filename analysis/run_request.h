// What `layerlab run` is asked (RunRequest) and what it did (RunOutcome):
// analysis/run_pipeline.h runs it, analysis/run_steps.h holds its steps.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "layerlab/analysis/compare.h"
#include "layerlab/analysis/contrast.h"
#include "layerlab/analysis/retina_sweep.h"
#include "layerlab/solvers/solver.h"

namespace layerlab {

struct RunRequest {
  std::string scene;  // the scene file, with "solve" and "run" sections
  std::string out;    // the output folder
  // Override the main solve's own (the scene's "solve" section).
  std::optional<int> iterations, threads;
  bool keep_images = false;  // also keep the retinal images in RunOutcome::retina (Python's run)
  // A store of target renders by key that other runs read too (a sweep's DIR/targets:
  // analysis/target_cache.h), or "": the run keeps its render in OUT/target only.
  std::string shared_renders;
  // A solve folder (an earlier run's OUT/solve) whose patterns start the main
  // solve when the display's layers have their shapes; else the solve starts
  // cold and RunOutcome::warm_started says so. "": cold.
  std::string warm_start;
};

struct RunOutcome {
  std::vector<std::string> written;    // relative to the output folder, sorted
  std::vector<std::string> removed;    // files an earlier run recorded there and this one did not write
  std::vector<std::string> recovered;  // what was cleared of interrupted or killed runs first
  std::vector<std::string> warnings;
  bool solved = false;
  bool warm_started = false;  // the main solve began from RunRequest::warm_start's patterns
  SolverReport report;        // of the main solve, when solved
  std::string compare_table;  // empty without a comparison
  std::string index_html;     // the report's absolute path
  // What the steps computed, as the files hold it: the main solve's patterns,
  // each retinal state (its images with RunRequest::keep_images), the contrast
  // curves, and the comparison's rows with each row's scene file.
  Patterns patterns;
  std::vector<RetinaStateResult> retina;
  std::vector<ContrastCurve> contrast;
  std::vector<CompareResult> compare;
  std::vector<std::string> compare_scenes;
};

}  // namespace layerlab
