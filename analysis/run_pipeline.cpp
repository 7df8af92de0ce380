#include "analysis/run_pipeline.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "analysis/compare.h"
#include "analysis/contrast.h"
#include "analysis/html_report.h"
#include "analysis/report_parts.h"
#include "analysis/retina_sweep.h"
#include "analysis/run_config.h"
#include "analysis/target_source.h"
#include "framework/atomic_file.h"
#include "framework/error.h"
#include "framework/lightfield_io.h"
#include "framework/png_writer.h"
#include "framework/progress.h"
#include "framework/staged_output.h"
#include "solvers/solution_writer.h"
#include "solvers/solve_config.h"
#include "systems/compile.h"
#include "systems/system_report.h"

namespace layerlab {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double Since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

std::string Psnr(double db) {
  char text[32];
  std::snprintf(text, sizeof text, std::isinf(db) ? "inf" : "%.2f dB", db);
  return text;
}

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
  bool has_target() const { return !solve.target.empty() || !solve.target_scene.empty(); }
};

RunInputs ReadInputs(const std::string& file, std::optional<int> iterations, std::optional<int> threads) {
  RunInputs in{LoadScene(file), {}, {}, {}, fs::path(file).stem().string(), {}, {}};
  in.system = Compile(in.scene);
  in.solve = ReadSolveConfig(in.scene, in.system);
  if (iterations && *iterations <= 0) throw Error("--iterations: must be positive");
  in.solve.options.iterations = iterations.value_or(in.solve.options.iterations);
  in.solve.options.threads = threads.value_or(in.solve.options.threads);
  in.run = ReadRunConfig(in.scene, in.system);
  const Location run_at{file, "/run"};
  if (!in.has_target()) {
    if (in.run.retina.enabled)
      throw Error(
          run_at.child("retina"),
          "retinal images need a target to factorize: give \"solve\": {\"target\": ...} or {\"target_scene\": ...}");
    if (in.run.compare.enabled)
      throw Error(run_at.child("compare"),
                  "a comparison needs a target: give \"solve\": {\"target\": ...} or {\"target_scene\": ...}");
    if (!in.run.contrast.enabled)
      throw Error(file +
                  ": nothing to run: give a target in the \"solve\" section or analyses in a \"run\" section "
                  "(docs/run-section.md)");
  }
  if (std::string why = UnsuitableSolver(in.solve.solver, in.system); !why.empty())
    throw Error(Location{file, "/solve/solver"}, "the solver " + in.solve.solver + " " + why);
  if (in.run.compare.enabled) {
    std::vector<std::string> files = {file};
    files.insert(files.end(), in.run.compare.scenes.begin(), in.run.compare.scenes.end());
    for (size_t k = 1; k < files.size(); ++k) {
      Scene other = LoadScene(files[k]);
      OtherDisplay d{fs::path(files[k]).stem().string(), Compile(other), {}};
      d.config = ReadSolveConfig(other, d.system);
      // Without a "solve" section of its own, a display runs as this one does, so that the runs compare.
      if (!other.document.contains("solve") && d.config.solver == in.solve.solver) {
        d.config.options = in.solve.options;
        d.config.sampling = in.solve.sampling;
        d.own_options = false;
      }
      in.compare.push_back(std::move(d));
    }
  }
  if (in.run.contrast.enabled) {
    ContrastDisplay self{in.name, in.system, in.solve.solver, in.solve.options, true};
    in.contrast.push_back(self);
    for (const std::string& other : in.run.contrast.scenes) in.contrast.push_back(LoadContrastDisplay(other));
  }
  return in;
}

}  // namespace

const std::vector<std::string>& RunOutputRoots() {
  static const std::vector<std::string> roots = {"system.txt", "system.json", "index.html", "target",
                                                 "solve",      "retina",      "contrast",   "compare"};
  return roots;
}

RunOutcome RunPipeline(const RunRequest& request) {
  const auto run_start = Clock::now();
  RunInputs in = ReadInputs(request.scene, request.iterations, request.threads);
  if (in.has_target()) RefuseSolveBeyondMemory(in.system, in.solve, in.solve.options.threads);
  std::vector<NamedInput> inputs = {
      {request.scene, "the scene"}, {in.solve.target, "the target"}, {in.solve.target_scene, "the target scene"}};
  for (const std::string& s : in.run.compare.scenes) inputs.push_back({s, "a compared scene"});
  for (const std::string& s : in.run.contrast.scenes) inputs.push_back({s, "a contrast scene"});
  StagedOutput stage(request.out, "run", RunOutputRoots(), inputs);
  RunOutcome outcome;
  outcome.recovered = stage.recovered();
  for (const std::string& line : outcome.recovered) Note("run: " + line);
  const fs::path out = stage.staging();  // everything is written here, then switched into place

  RunReportPage page;
  SolverReport report;
  try {
    page = CommandPage("run", request.scene, in.scene.name.empty() ? in.name : in.scene.name, in.scene.description,
                       "layerlab run " + request.scene + " --out " + request.out +
                           (request.iterations ? " --iterations " + std::to_string(*request.iterations) : ""));
    page.system = &in.system;
    WriteFileAtomically((out / "system.txt").string(), FormatSystemTable(in.system));
    WriteFileAtomically((out / "system.json").string(), SystemToJson(in.system).dump(2) + "\n");
    page.system_links = {{"system.txt", "system.txt"}, {"system.json", "system.json"}};
    auto step = [&](const std::string& what, Clock::time_point start) { page.steps.emplace_back(what, Since(start)); };

    // Target and solve.
    std::unique_ptr<Target> target;
    std::unique_ptr<DisplayModel> model;
    Patterns patterns;
    if (in.has_target()) {
      auto start = Clock::now();
      // A rendered target is kept in OUT/target and reused by the next run while its scene is unchanged.
      const RenderCache cache{(fs::path(request.out) / "target").string(), (out / "target").string()};
      target = LoadOrRenderTarget(in.solve, "target", &cache);
      fs::create_directories(out / "target");
      WriteCenterView(target->light_field, (out / "target" / "center_view.png").string());
      std::vector<std::pair<std::string, std::string>> links;
      if (target->rendered)
        links = {{"light field", "target/lightfield/lightfield.json"}, {"render record", "target/render.json"}};
      const LightFieldGeometry& g = target->light_field.geometry;
      page.target_source = DescribeTarget(*target);
      page.target = Picture("center view (sRGB, 1 = white)", "target/center_view.png", links);
      step(target->reused     ? "read the target's earlier render"
           : target->rendered ? "render the target"
                              : "load the target",
           start);

      start = Clock::now();
      model = std::make_unique<DisplayModel>(in.system, g, in.solve.sampling);
      SolverOptions options = in.solve.options;
      AttachRetinalTarget(*target, &options);
      Progress progress("solve " + in.solve.solver, options.iterations);
      options.progress = [&](const IterationRecord& row) {
        progress.Update(row.iteration, "iterations  PSNR " + Psnr(row.psnr_db));
      };
      report =
          SolverRegistry::Builtins().create(in.solve.solver)->Solve(*model, target->light_field, options, &patterns);
      progress.Finish(report.BriefReport());
      for (const std::string& w : TargetGeometryWarnings(in.system, g)) page.warnings.push_back("target: " + w);
      for (const std::string& w : report.warnings) page.warnings.push_back("solve: " + w);
      if (!report.IsSolutionUsable())
        throw Error("the solve failed: " + report.message + "; the report was not written");
      const std::string solve_dir = (out / "solve").string();
      WriteSolution(*model, patterns, report, solve_dir, {.write_lightfield = in.run.write_lightfield});
      AddSolveToPage(in.system, patterns, report, solve_dir, "solve/", in.run.write_lightfield, &page);
      step("solve (" + in.solve.solver + ", " + std::to_string(report.iterations) + " iterations)", start);
    }

    if (in.run.retina.enabled) {
      auto start = Clock::now();
      const RetinaRunConfig& r = in.run.retina;
      const SceneRadiance natural =
          r.natural ? target->Natural(r.natural_traced ? Target::Viewing::kTraced : Target::Viewing::kLightField)
                    : SceneRadiance{};
      RetinaSweepOptions sweep{r.states(), r.resolution, r.field_x, r.field_y, request.keep_images};
      Progress progress("retina", sweep.states.size());
      std::vector<RetinaStateResult> states =
          WriteRetinaSweep(*model, patterns, natural, sweep, (out / "retina").string(),
                           [&](size_t done, size_t, const RetinaStateResult& s) {
                             progress.Update(done, "accommodation states traced (" + s.name + ")");
                           });
      progress.Finish(std::to_string(states.size()) + " states");
      AddRetinaToPage(states, r.accommodation, bool(natural), model->white_luminance(), "retina/", &page);
      step("retina (" + std::to_string(states.size()) + " accommodation states)", start);
      outcome.retina = std::move(states);
    }

    if (in.run.contrast.enabled) {
      auto start = Clock::now();
      ContrastOptions options = in.run.contrast.options;
      const size_t total = in.contrast.size() * options.frequencies.size() * options.target_diopters.size();
      options.show_progress = true;
      for (const std::string& w : ContrastWarnings(in.contrast, options)) page.warnings.push_back("contrast: " + w);
      outcome.contrast = RunContrast(in.contrast, options);
      AddContrastToPage(outcome.contrast, (out / "contrast").string(), "contrast/", &page);
      step("contrast sweep (" + std::to_string(total) + " solves)", start);
    }

    if (in.run.compare.enabled) {
      auto start = Clock::now();
      const CompareRunConfig& c = in.run.compare;
      std::vector<std::pair<std::string, const DisplaySystem*>> displays = {{in.name, &in.system}};
      std::vector<const SolveConfig*> configs = {&in.solve};
      for (const OtherDisplay& d : in.compare) displays.push_back({d.name, &d.system}), configs.push_back(&d.config);
      for (size_t k = 0; k < displays.size(); ++k) {
        std::vector<std::string> solvers = c.solvers.empty() ? std::vector<std::string>{configs[k]->solver} : c.solvers;
        for (const std::string& solver : solvers) {
          const auto& [name, system] = displays[k];
          if (std::string why = UnsuitableSolver(solver, *system); !why.empty()) {
            page.warnings.push_back("compare: skipped " + name + " / " + solver + ": the solver " + why);
            continue;
          }
          // A display runs with its scene's own options when it has a "solve" section of its own (ReadInputs).
          const bool own = solver == configs[k]->solver && (k == 0 || in.compare[k - 1].own_options);
          SolverOptions base =
              solver == configs[k]->solver ? configs[k]->options : SolverRegistry::Builtins().find(solver)->defaults;
          base.iterations = c.iterations.value_or(base.iterations);
          base.time_budget = c.time_budget.value_or(base.time_budget);
          std::vector<std::string> skipped;
          const std::vector<CompareRun> runs = ObjectiveRuns(
              {name, *system, solver, base, configs[k]->sampling, own ? "scene" : "shared"}, c.objectives, &skipped);
          for (const std::string& line : skipped) page.warnings.push_back("compare: skipped " + line);
          for (const CompareRun& run : runs) {
            // The main solve already ran this: its trace, cut at the budget, is the row.
            const bool main_ran_it = k == 0 && solver == in.solve.solver && !c.iterations &&
                                     run.options.objective == in.solve.options.objective &&
                                     (!run.options.measure_focal_stack || in.solve.options.measure_focal_stack);
            if (main_ran_it)
              if (std::optional<SolverReport> main = c.time_budget ? ReportWithTimeBudget(report, *c.time_budget)
                                                                   : std::optional<SolverReport>(report)) {
                outcome.compare_scenes.push_back(system->file);
                page.compare.push_back({name, solver, *main, system->brightness_efficiency,
                                        system->luminance_efficiency, system->subframes,
                                        system->subframes * system->frame_rate, "scene"});
                continue;
              }
            CompareRun attached = run;
            AttachRetinalTarget(*target, &attached.options);
            CompareResult result = RunComparison({attached}, target->light_field, true).front();
            if (!result.report.IsSolutionUsable())
              throw Error("compare: " + RunLabel(result) + " failed: " + result.report.message);
            outcome.compare_scenes.push_back(system->file);
            page.compare.push_back(std::move(result));
          }
        }
      }
      AddCompareToPage(page.compare, (out / "compare").string(), "compare/", &page);
      step("compare (" + std::to_string(page.compare.size()) + " runs)", start);
      outcome.compare_table = CompareTable(page.compare);
      outcome.compare = page.compare;
    }

    page.steps.emplace_back("total", Since(run_start));
    for (const std::string& w : in.system.warnings)
      outcome.warnings.push_back("compile: " + w);  // shown by the page's system table
    outcome.warnings.insert(outcome.warnings.end(), page.warnings.begin(), page.warnings.end());
    WriteReportPage(page, out.string());
    outcome.patterns = std::move(patterns);
  } catch (const Error& e) {
    throw stage.Explain(e);
  }
  StagedOutput::Switched switched = stage.Commit();
  outcome.written = std::move(switched.written);
  outcome.removed = std::move(switched.removed);
  outcome.solved = page.solved;
  outcome.report = report;
  outcome.index_html = (fs::absolute(request.out) / "index.html").lexically_normal().string();
  return outcome;
}

}  // namespace layerlab
