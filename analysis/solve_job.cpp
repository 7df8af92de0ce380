#include "layerlab/analysis/solve_job.h"

#include <cmath>
#include <cstdio>
#include <optional>

#include "layerlab/analysis/flicker_check.h"
#include "layerlab/analysis/report_parts.h"
#include "layerlab/framework/progress.h"
#include "layerlab/solvers/solution_writer.h"

namespace layerlab {
namespace {

std::string Psnr(double db) {
  char text[32];
  std::snprintf(text, sizeof text, std::isinf(db) ? "inf" : "%.2f dB", db);
  return text;
}

}  // namespace

void UseSolver(const std::string& solver, SolveConfig* config) {
  config->options = SolverRegistry::Builtins().get(solver).defaults;
  config->solver = solver;
}

SolveConfig SolveJobConfig(const Scene& scene, const DisplaySystem& system, const std::string& solver) {
  SolveConfig config = ReadSolveConfig(scene, system);
  if (!solver.empty() && solver != config.solver) UseSolver(solver, &config);
  return config;
}

SolvedJob RunSolveJob(const SolveJob& job, const LightField& views, const Target* target) {
  SolvedJob solved;
  solved.model = std::make_shared<DisplayModel>(*job.system, views.geometry, job.config.sampling);
  SolverOptions options = job.config.options;
  if (target) AttachRetinalTarget(*target, &options);
  if (job.before_solve) job.before_solve(*solved.model, &options);
  std::optional<Progress> progress;
  if (!job.progress_label.empty()) {
    progress.emplace(job.progress_label, options.iterations);
    options.progress = [&, earlier = options.progress](const IterationRecord& row) {
      if (earlier) earlier(row);  // a hook's own (before_solve)
      progress->Update(row.iteration, "iterations  PSNR " + Psnr(row.psnr_db));
    };
  }
  {
    const ScopedSolveRanks partitioned(job.ranks);
    solved.report =
        SolverRegistry::Builtins().create(job.config.solver)->Solve(*solved.model, views, options, &solved.patterns);
    AddFlickerCheck(*solved.model, solved.patterns, &solved.report);  // over every rank's rays
  }
  if (progress)
    progress->Finish(job.progress_brief ? solved.report.BriefReport() : ToString(solved.report.termination));
  return solved;
}

void WriteSolveJob(const DisplayModel& written, const DisplaySystem& system, const SolvedJob& solved,
                   const std::string& folder, const std::string& prefix, bool write_lightfield, RunReportPage* page) {
  WriteSolution(written, solved.patterns, solved.report, folder, {.write_lightfield = write_lightfield});
  AddSolveToPage(system, solved.patterns, solved.report, folder, prefix, write_lightfield, page);
}

}  // namespace layerlab
