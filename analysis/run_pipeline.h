// The main job of `layerlab run` (docs/run-section.md) as a library call, so
// that the command, a Python module and a C++ program run the same code:
// every input is read and checked first, then the steps the scene declares
// run in order, each long step with a progress line on stderr.
//
// The results are built in a staging folder inside the output folder
// (framework/staged_output.h) and switched into place only when every file
// is complete: a run that fails leaves the folder as it was, byte for byte.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "analysis/compare.h"
#include "analysis/contrast.h"
#include "analysis/retina_sweep.h"
#include "solvers/solver.h"

namespace layerlab {

struct RunRequest {
  std::string scene;  // the scene file, with "solve" and "run" sections
  std::string out;    // the output folder
  // Override the main solve's own (the scene's "solve" section).
  std::optional<int> iterations, threads;
  bool keep_images = false;  // also keep the retinal images in RunOutcome::retina (Python's run)
};

struct RunOutcome {
  std::vector<std::string> written;    // relative to the output folder, sorted
  std::vector<std::string> removed;    // files an earlier run recorded there and this one did not write
  std::vector<std::string> recovered;  // what was cleared of interrupted or killed runs first
  std::vector<std::string> warnings;
  bool solved = false;
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

// Throws layerlab::Error (the output folder then as it was).
RunOutcome RunPipeline(const RunRequest& request);

// The files and folders a run owns in its output folder.
const std::vector<std::string>& RunOutputRoots();

}  // namespace layerlab
