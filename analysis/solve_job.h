// One solve job: the sequence `layerlab solve`, `layerlab run` (and so
// `sweep`) and Python's solve() share, in named steps:
//
//   SolveJobConfig   the scene's "solve" section, switched to the solver a caller names
//   (overrides)      the caller's flags or keyword arguments; SolverOptions::IsValid checks them
//   (memory check)   RefuseSolveBeyondMemory (analysis/target_source.h), before a view is read
//   (staging)        the caller's StagedOutput: a command's own folder, or the run's
//   RunSolveJob      the display model, the retinal target, progress, the solver
//   WriteSolveJob    WriteSolution and the report page's solve section
//
// The steps in parentheses differ by caller only in their values (which
// flags, which limit, which folder) and stay with the caller.
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "layerlab/analysis/html_report.h"
#include "layerlab/analysis/target_source.h"
#include "layerlab/framework/mpi_ranks.h"
#include "layerlab/solvers/solve_config.h"
#include "layerlab/solvers/solver.h"
#include "layerlab/systems/scene.h"

namespace layerlab {

// The scene's "solve" section (ReadSolveConfig), switched to `solver` with that
// solver's defaults when one is named and differs.
SolveConfig SolveJobConfig(const Scene& scene, const DisplaySystem& system, const std::string& solver = "");

// The solver a caller names, with its defaults; an unknown name is refused naming the known ones.
void UseSolver(const std::string& solver, SolveConfig* config);

struct SolveJob {
  const DisplaySystem* system = nullptr;
  SolveConfig config;                // the scene's, with the caller's overrides
  std::string progress_label;        // empty: no progress line (Python reports through its callback)
  bool progress_brief = false;       // end the progress line with the brief report, else with the termination
  const RankGroup* ranks = nullptr;  // rays partitioned across MPI ranks (framework/mpi_ranks.h)
  // Called with the model and the options just before the solver starts (checkpoints, resuming).
  std::function<void(const DisplayModel&, SolverOptions*)> before_solve;
};

struct SolvedJob {
  std::shared_ptr<DisplayModel> model;  // of the views solved
  Patterns patterns;
  SolverReport report;
};

// Solves for `views` (the target's, or this rank's block of them); `target`,
// when given, supplies a traced retinal target (AttachRetinalTarget) and must
// outlive the solve. A failed solve is returned as the report says it.
SolvedJob RunSolveJob(const SolveJob& job, const LightField& views, const Target* target);

// WriteSolution into `folder` and the page's solve section (previews, PSNR
// plot); `prefix` is the folder as the page sees it ("solve/" in the run's
// report, "" in the solve's own). `written` is the model of the whole light field.
void WriteSolveJob(const DisplayModel& written, const DisplaySystem& system, const SolvedJob& solved,
                   const std::string& folder, const std::string& prefix, bool write_lightfield, RunReportPage* page);

}  // namespace layerlab
