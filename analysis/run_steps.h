// The steps of `layerlab run` (analysis/run_pipeline.h): its inputs, read
// and checked first with every scene file read once, and its report
// sections, each a step that writes its folder and adds its section to the
// page. A new section is one file defining a RunSection and its line in
// RunSections() (analysis/run_sections.cpp), and its source in
// analysis/CMakeLists.txt.
#pragma once

#include <chrono>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "layerlab/analysis/contrast.h"
#include "layerlab/analysis/html_report.h"
#include "layerlab/analysis/run_config.h"
#include "layerlab/analysis/run_request.h"
#include "layerlab/analysis/solve_job.h"
#include "layerlab/analysis/target_source.h"
#include "layerlab/systems/scene.h"

namespace layerlab {

// A compare run of another scene, compiled before anything runs.
struct OtherDisplay {
  std::string name;
  DisplaySystem system;
  SolveConfig config;
  bool own_options = true;  // its own "solve" section; false: runs as the main scene does
};

struct RunInputs {
  Scene scene;
  DisplaySystem system;
  SolveConfig solve;
  RunConfig run;
  std::string name;  // the scene file's stem
  std::vector<OtherDisplay> compare;
  std::vector<ContrastDisplay> contrast;
  std::optional<ContrastDisplay> contrast_factorized_for;  // run.contrast.factorized_for's display
  LightFieldGeometry target_geometry;                      // read without the views, for the memory estimate
#if LAYERLAB_WITH_EMBREE
  std::unique_ptr<TargetScene> target_scene;  // read once: the estimate's geometry, then the render
#endif
  bool has_target() const { return !solve.target.empty() || !solve.target_scene.empty(); }
};

// Reads the scene and every file it names once, compiles each display and
// checks what the run declares before anything runs.
RunInputs ReadRunInputs(const RunRequest& request);

// What the steps share while the run is built in the staging folder `out`.
struct RunState {
  const RunRequest& request;
  RunInputs& in;
  std::filesystem::path out;
  RunReportPage page;
  RunOutcome outcome;
  std::unique_ptr<Target> target;  // the target step's
  SolvedJob solved;                // the solve step's: model, patterns, report
  bool ran_solve = false;
  bool warm_started = false;  // the solve began from RunRequest::warm_start
};

struct RunSection {
  std::string id;  // its folder in the output folder and its anchor in the page
  bool (*declared)(const RunInputs& in);
  // Writes the section's files, adds it to the page; returns the steps table's line for it.
  std::string (*run)(RunState& state);
};

// The sections in the order they run and the page shows them.
const std::vector<RunSection>& RunSections();

}  // namespace layerlab
