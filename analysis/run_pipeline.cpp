#include "layerlab/analysis/run_pipeline.h"

#include <chrono>
#include <filesystem>
#include <memory>
#include <string>

#include "layerlab/analysis/report_parts.h"
#include "layerlab/analysis/run_steps.h"
#include "layerlab/framework/atomic_file.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/progress.h"
#include "layerlab/framework/staged_output.h"
#include "layerlab/systems/system_report.h"

namespace layerlab {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double Since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// The staging step: everything is written into the staging folder, then switched into place.
StagedOutput StageRun(const RunRequest& request, const RunInputs& in) {
  std::vector<NamedInput> inputs = {
      {request.scene, "the scene"}, {in.solve.target, "the target"}, {in.solve.target_scene, "the target scene"}};
  for (const std::string& s : in.run.compare.scenes) inputs.push_back({s, "a compared scene"});
  for (const std::string& s : in.run.contrast.scenes) inputs.push_back({s, "a contrast scene"});
  return StagedOutput(request.out, "run", RunOutputRoots(), inputs);
}

// The page's frame and the compiled system beside it.
void WriteSystem(const RunRequest& request, RunState& s) {
  const RunInputs& in = s.in;
  s.page = CommandPage("run", request.scene, in.scene.name.empty() ? in.name : in.scene.name, in.scene.description,
                       "layerlab run " + request.scene + " --out " + request.out +
                           (request.iterations ? " --iterations " + std::to_string(*request.iterations) : ""));
  s.page.system = &in.system;
  WriteFileAtomically((s.out / "system.txt").string(), FormatSystemTable(in.system));
  WriteFileAtomically((s.out / "system.json").string(), SystemToJson(in.system).dump(2) + "\n");
  s.page.system_links = {{"system.txt", "system.txt"}, {"system.json", "system.json"}};
}

// Every declared section in order, each timed as a line of the steps table.
void RunDeclaredSections(RunState& s) {
  for (const RunSection& section : RunSections()) {
    if (!section.declared(s.in)) continue;
    const auto start = Clock::now();
    const std::string what = section.run(s);
    s.page.steps.emplace_back(what, Since(start));
  }
}

// The page, and the warnings the outcome reports.
void FinishPage(RunState& s, Clock::time_point run_start) {
  s.page.steps.emplace_back("total", Since(run_start));
  for (const std::string& w : s.in.system.warnings)
    s.outcome.warnings.push_back("compile: " + w);  // shown by the page's system table
  s.outcome.warnings.insert(s.outcome.warnings.end(), s.page.warnings.begin(), s.page.warnings.end());
  WriteReportPage(s.page, s.out.string());
  s.outcome.patterns = std::move(s.solved.patterns);
}

}  // namespace

const std::vector<std::string>& RunOutputRoots() {
  static const std::vector<std::string> roots = [] {
    std::vector<std::string> r = {"system.txt", "system.json", "index.html"};
    for (const RunSection& section : RunSections()) r.push_back(section.id);
    return r;
  }();
  return roots;
}

RunOutcome RunPipeline(const RunRequest& request) {
  const auto run_start = Clock::now();
  RunInputs in = ReadRunInputs(request);
  if (in.has_target())
    RefuseSolveBeyondMemory(in.system, in.target_geometry, in.solve, in.solve.options.threads, 0, "");
  StagedOutput stage = StageRun(request, in);
  RunState s{request, in, stage.staging(), {}, {}, {}, {}};
  s.outcome.recovered = stage.recovered();
  for (const std::string& line : s.outcome.recovered) Note("run: " + line);
  try {
    WriteSystem(request, s);
    RunDeclaredSections(s);
    FinishPage(s, run_start);
  } catch (const Error& e) {
    throw stage.Explain(e);
  }
  StagedOutput::Switched switched = stage.Commit();
  RunOutcome outcome = std::move(s.outcome);
  outcome.written = std::move(switched.written);
  outcome.removed = std::move(switched.removed);
  outcome.solved = s.ran_solve;
  outcome.warm_started = s.warm_started;
  outcome.report = s.solved.report;
  outcome.index_html = (fs::absolute(request.out) / "index.html").lexically_normal().string();
  return outcome;
}

}  // namespace layerlab
