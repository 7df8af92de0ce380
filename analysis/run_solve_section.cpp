// The run's main solve: the solve job (analysis/solve_job.h) on the target,
// written into OUT/solve.
#include "layerlab/analysis/run_steps.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/progress.h"
#include "layerlab/solvers/solution_writer.h"

namespace layerlab {
namespace {

std::string RunSolve(RunState& s) {
  const RunInputs& in = s.in;
  SolveJob job;
  job.system = &in.system;
  job.config = in.solve;
  job.progress_label = "solve " + in.solve.solver;
  job.progress_brief = true;
  Patterns warm;
  if (!s.request.warm_start.empty())
    job.before_solve = [&](const DisplayModel& model, SolverOptions* options) {
      try {
        warm = ReadPatterns(model, s.request.warm_start);
      } catch (const Error& e) {
        Note("solve: starting cold, not from " + s.request.warm_start + ": " + e.what());
        return;
      }
      options->initial_patterns = &warm;
      s.warm_started = true;
    };
  s.solved = RunSolveJob(job, s.target->light_field, s.target.get());
  const SolverReport& report = s.solved.report;
  for (const std::string& w : TargetGeometryWarnings(in.system, s.target->light_field.geometry))
    s.page.warnings.push_back("target: " + w);
  for (const std::string& w : report.warnings) s.page.warnings.push_back("solve: " + w);
  if (!report.IsSolutionUsable()) throw Error("the solve failed: " + report.message + "; the report was not written");
  WriteSolveJob(*s.solved.model, in.system, s.solved, (s.out / "solve").string(), "solve/", in.run.write_lightfield,
                &s.page);
  s.ran_solve = true;
  return "solve (" + in.solve.solver + ", " + std::to_string(report.iterations) + " iterations)";
}

}  // namespace

RunSection SolveRunSection() {
  return {"solve", [](const RunInputs& in) { return in.has_target(); }, RunSolve};
}

}  // namespace layerlab
