#include "analysis/compare.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <set>

#include "analysis/svg_plot.h"
#include "framework/error.h"
#include "framework/progress.h"
#include "solvers/objective.h"
#include "solvers/solve_config.h"
#include "systems/compile.h"
#include "systems/display_model.h"

namespace layerlab {
namespace {

std::string Psnr(double db) { return FormatPsnr(db, 3); }

}  // namespace

std::vector<std::string> SuitableSolvers(const DisplaySystem& system, const SolverRegistry& registry) {
  std::vector<std::string> out;
  for (const std::string& name : registry.names())
    if (registry.get(name).Unsuitable(system).empty()) out.push_back(name);
  return out;
}

std::vector<CompareRun> CompareRunsOf(const std::vector<std::string>& scene_files, const CompareSelection& selection,
                                      std::vector<std::string>* skipped) {
  const SolverRegistry& registry = SolverRegistry::Builtins();
  const bool all = selection.solvers.size() == 1 && selection.solvers.front() == "all";
  if (!all)
    for (const std::string& name : selection.solvers) registry.get(name);  // names the known ones
  std::vector<CompareRun> runs;
  for (const std::string& file : scene_files) {
    Scene scene = LoadScene(file);
    DisplaySystem system = Compile(scene);
    SolveConfig config = ReadSolveConfig(scene, system);
    std::vector<std::string> solvers = all ? SuitableSolvers(system) : selection.solvers;
    if (solvers.empty()) solvers.push_back(config.solver);
    const std::string name = std::filesystem::path(file).stem().string();
    for (const std::string& solver : solvers) {
      if (std::string why = UnsuitableSolver(solver, system); !why.empty()) {
        if (skipped) skipped->push_back(name + " / " + solver + ": the solver " + why);
        continue;
      }
      // Like for like unless asked: every row runs its solver with the same options.
      const bool own = selection.scene_options && solver == config.solver;
      SolverOptions options = own ? config.options : registry.find(solver)->defaults;
      options.iterations = selection.iterations.value_or(options.iterations);
      options.time_budget = selection.time_budget.value_or(options.time_budget);
      runs.push_back(
          {name, system, solver, options, own ? config.sampling : Sampling::kNearest, own ? "scene" : "shared"});
    }
  }
  if (runs.empty()) throw Error("compare: no display and solver fit together; nothing to run");
  return runs;
}

std::vector<std::string> CompareWarnings(const std::vector<CompareRun>& runs, const std::vector<CompareResult>& results,
                                         const LightFieldGeometry& target) {
  std::vector<std::string> warnings;
  std::set<std::string> seen;
  for (const CompareRun& r : runs)
    if (seen.insert(r.display).second) {
      std::vector<std::string> found = r.system.warnings;
      for (const std::string& w : TargetGeometryWarnings(r.system, target)) found.push_back(w);
      for (const std::string& w : found) warnings.push_back(r.display + ": " + w);
    }
  for (const CompareResult& r : results)
    for (const std::string& w : r.report.warnings) warnings.push_back(r.display + " / " + r.solver + ": " + w);
  return warnings;
}

std::vector<CompareResult> RunComparison(const std::vector<CompareRun>& runs, const LightField& target,
                                         bool show_progress, const SolverRegistry& registry) {
  std::vector<CompareResult> results;
  for (const CompareRun& run : runs) {
    DisplayModel model(run.system, target.geometry, run.sampling);
    SolverOptions options = run.options;
    const std::string label = run.display + " / " + run.solver;
    std::optional<Progress> progress;
    if (show_progress) {
      progress.emplace("compare " + label, options.iterations);
      options.progress = [&](const IterationRecord& row) {
        progress->Update(row.iteration, "iterations  PSNR " + Psnr(row.psnr_db) + " dB");
      };
    }
    Patterns t;
    CompareResult r{run.display,
                    run.solver,
                    {},
                    run.system.brightness_efficiency,
                    run.system.luminance_efficiency,
                    run.system.subframes,
                    run.system.subframes * run.system.frame_rate,
                    run.options_from};
    r.report = registry.create(run.solver)->Solve(model, target, options, &t);
    if (progress) progress->Finish(r.report.BriefReport());
    results.push_back(std::move(r));
  }
  return results;
}

std::string CompareTable(const std::vector<CompareResult>& results) {
  std::string out =
      "display                      solver                  PSNR (dB)   seconds  iterations  subframes  panel (Hz)  "
      "brightness (lum.)  brightness R G B       options  termination\n";
  for (const CompareResult& r : results) {
    char line[400];
    std::snprintf(line, sizeof line, "%-28s %-22s %10s %9.2f %11d %10d %11.0f %18.4f  %.4f %.4f %.4f   %-7s  %s\n",
                  r.display.c_str(), r.solver.c_str(), Psnr(r.report.final_psnr_db).c_str(), r.report.seconds,
                  r.report.iterations, r.subframes, r.panel_refresh_hz, r.luminance_efficiency,
                  r.brightness_efficiency[0], r.brightness_efficiency[1], r.brightness_efficiency[2],
                  r.options_from.c_str(), ToString(r.report.termination).c_str());
    out += line;
  }
  return out;
}

std::string CompareCsv(const std::vector<CompareResult>& results) {
  std::string out =
      "display,solver,final_psnr_db,seconds,iterations,subframes,panel_refresh_hz,luminance_efficiency,efficiency_r,"
      "efficiency_g,efficiency_b,termination,solver_options\n";
  for (const CompareResult& r : results) {
    char line[400];
    std::snprintf(line, sizeof line, "%s,%s,%s,%.6f,%d,%d,%.3f,%.6f,%.6f,%.6f,%.6f,%s,%s\n", r.display.c_str(),
                  r.solver.c_str(), Psnr(r.report.final_psnr_db).c_str(), r.report.seconds, r.report.iterations,
                  r.subframes, r.panel_refresh_hz, r.luminance_efficiency, r.brightness_efficiency[0],
                  r.brightness_efficiency[1], r.brightness_efficiency[2], ToString(r.report.termination).c_str(),
                  r.options_from.c_str());
    out += line;
  }
  return out;
}

std::string TracesCsv(const std::vector<CompareResult>& results) {
  std::string out = "display,solver,iteration,seconds,objective,psnr_db\n";
  for (const CompareResult& r : results)
    for (const IterationRecord& row : r.report.trace) {
      char line[300];
      std::snprintf(line, sizeof line, "%s,%s,%d,%.6f,%.9g,%s\n", r.display.c_str(), r.solver.c_str(), row.iteration,
                    row.seconds, row.objective, Psnr(row.psnr_db).c_str());
      out += line;
    }
  return out;
}

std::string PsnrAgainstTimeSvg(const std::vector<CompareResult>& results) {
  static const char* kColors[] = {"#d62728", "#1f77b4", "#2ca02c", "#ff7f0e",
                                  "#9467bd", "#8c564b", "#e377c2", "#17becf"};
  PlotPanel panel;
  panel.title = "PSNR against wall time";
  panel.x_label = "wall time (s)";
  panel.y_label = "PSNR (dB)";
  double t_max = 0, y_min = INFINITY, y_max = -INFINITY;
  for (size_t k = 0; k < results.size(); ++k) {
    PlotLine line{results[k].display + " / " + results[k].solver, kColors[k % 8], k >= 8, {}, {}};
    for (const IterationRecord& row : results[k].report.trace) {
      if (!std::isfinite(row.psnr_db)) continue;
      line.x.push_back(row.seconds);
      line.y.push_back(row.psnr_db);
      t_max = std::max(t_max, row.seconds);
      // The first iterate (often the flat initial guess) would squash the interesting range.
      if (row.iteration > 0) y_min = std::min(y_min, row.psnr_db);
      y_max = std::max(y_max, row.psnr_db);
    }
    panel.lines.push_back(std::move(line));
  }
  if (!std::isfinite(y_min)) y_min = 0, y_max = 1;
  panel.x_max = t_max > 0 ? t_max * 1.02 : 1;
  panel.y_min = std::floor(y_min - 0.5);
  panel.y_max = std::ceil(y_max + 0.5);
  return RenderSvg({panel}, 1, "");
}

}  // namespace layerlab
