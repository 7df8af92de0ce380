#include "layerlab/analysis/compare.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <optional>
#include <set>

#include "layerlab/analysis/eyebox_map.h"
#include "layerlab/analysis/flicker_check.h"
#include "layerlab/analysis/svg_plot.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/progress.h"
#include "layerlab/framework/units.h"
#include "layerlab/retina/lightfield_radiance.h"
#include "layerlab/solvers/objective.h"
#include "layerlab/solvers/solve_config.h"
#include "layerlab/solvers/trace_columns.h"
#include "layerlab/systems/compile.h"
#include "layerlab/systems/display_model.h"
#include "layerlab/systems/eye_pose_limits.h"
#include "layerlab/systems/lc_response.h"
#include "layerlab/systems/panel_diffraction.h"

namespace layerlab {
namespace {

std::string Psnr(double db) { return FormatPsnr(db, 3); }
// A CSV field: empty where a run did not measure it.
std::string PsnrField(double db) { return std::isnan(db) ? "" : Psnr(db); }

ObjectiveKind ObjectiveOf(const SolverReport& report) {
  return ObjectiveKindNamed(report.objective).value_or(ObjectiveKind::kLightField);
}

bool Contains(const std::vector<ObjectiveKind>& objectives, ObjectiveKind k) {
  return std::find(objectives.begin(), objectives.end(), k) != objectives.end();
}

}  // namespace

std::string RunLabel(const std::string& display, const std::string& solver, ObjectiveKind objective) {
  return display + " / " + solver + (objective == ObjectiveKind::kRetinal ? " / retinal" : "");
}

std::string RunLabel(const CompareResult& result) {
  return RunLabel(result.display, result.solver, ObjectiveOf(result.report));
}

std::vector<const TraceColumn*> MeasuredMetricColumns(const std::vector<CompareResult>& results) {
  std::vector<const TraceColumn*> out;
  for (const TraceColumn& c : TraceColumns()) {
    if (c.kind != TraceValueKind::kScore) continue;
    for (const CompareResult& r : results)
      if (Measured(c, r.report.trace)) {
        out.push_back(&c);
        break;
      }
  }
  return out;
}

double FinalTraceValue(const TraceColumn& column, const SolverReport& report) {
  return report.trace.empty() ? std::numeric_limits<double>::quiet_NaN() : column.value(report.trace.back());
}

std::string MetricHeading(const TraceColumn& column) {
  const std::string name = std::string(column.name).substr(std::string("focal_stack_").size());
  if (name == "jnd") return "JND";
  return name == "ms_ssim" ? "MS-SSIM" : name == "ssim" ? "SSIM" : name;
}

double FinalFocalStackPsnr(const SolverReport& report) {
  return report.trace.empty() ? std::numeric_limits<double>::quiet_NaN() : report.trace.back().focal_stack_psnr_db;
}

SolverOptions WithObjective(SolverOptions options, ObjectiveKind objective,
                            const std::vector<ObjectiveKind>& objectives,
                            const std::vector<const RetinalMetric*>& metrics) {
  options.objective = objective;
  if (objective == ObjectiveKind::kLightField && Contains(objectives, ObjectiveKind::kRetinal))
    options.measure_focal_stack = true;
  if (metrics.size() > 1 || (metrics.size() == 1 && metrics[0]->name != "psnr")) {
    options.measure_metrics = metrics;
    if (objective == ObjectiveKind::kLightField) options.measure_focal_stack = true;
  }
  return options;
}

std::vector<CompareRun> ObjectiveRuns(const CompareRun& run, const std::vector<ObjectiveKind>& objectives,
                                      std::vector<std::string>* skipped, const SolverRegistry& registry,
                                      const std::vector<const RetinalMetric*>& metrics) {
  std::vector<CompareRun> runs;
  for (ObjectiveKind objective : objectives.empty() ? std::vector<ObjectiveKind>{run.options.objective} : objectives) {
    if (std::string why = ObjectiveRefusal(run.solver, objective, registry); !why.empty()) {
      if (skipped) skipped->push_back(RunLabel(run.display, run.solver, objective) + ": " + why);
      continue;
    }
    runs.push_back(run);
    runs.back().options = WithObjective(run.options, objective, objectives, metrics);
  }
  return runs;
}

std::vector<std::string> SuitableSolvers(const DisplaySystem& system, const SolverRegistry& registry) {
  std::vector<std::string> out;
  for (const std::string& name : registry.names())
    if (registry.get(name).Unsuitable(system).empty()) out.push_back(name);
  return out;
}

std::string CompareRefusal(const std::string& solver, const DisplaySystem& system, const SolverOptions& physics,
                           const SolverRegistry& registry) {
  if (std::string why = UnsuitableSolver(solver, system, registry); !why.empty()) return why;
  // The panels' diffraction and response are the display's physics, not a solver's setting: every row sees
  // them, or is skipped.
  const SolverType& type = registry.get(solver);
  if (physics.panel_diffraction && !type.panel_diffraction && !PanelDiffraction(system).empty())
    return "does not model the panels' diffraction, which the scene's solve asks for (\"panel_diffraction\")";
  if (physics.lc_response && !type.lc_response && ResponseMatters(system))
    return "does not model the panels' liquid-crystal response, which the scene's solve asks for (\"lc_response\")";
  return "";
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
      if (const std::string why = CompareRefusal(solver, system, config.options, registry); !why.empty()) {
        if (skipped) skipped->push_back(name + " / " + solver + ": the solver " + why);
        continue;
      }
      // Like for like unless asked: every row runs its solver with the same options.
      const bool own = selection.scene_options && solver == config.solver;
      SolverOptions options = own ? config.options : registry.find(solver)->defaults;
      options.iterations = selection.iterations.value_or(options.iterations);
      options.time_budget = selection.time_budget.value_or(options.time_budget);
      options.panel_diffraction = config.options.panel_diffraction;
      options.lc_response = config.options.lc_response;
      options.metric_settings = selection.metric_settings;
      const CompareRun run{
          name, system, solver, options, own ? config.sampling : Sampling::kNearest, own ? "scene" : "shared"};
      for (CompareRun& r : ObjectiveRuns(run, selection.objectives, skipped, registry, selection.metrics))
        runs.push_back(std::move(r));
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
    for (const std::string& w : r.report.warnings) warnings.push_back(RunLabel(r) + ": " + w);
  return warnings;
}

namespace {

// The solution's eyebox over the pupil positions inside the light field's eyebox.
EyeboxExtent MeasureEyebox(const DisplayModel& model, const Patterns& t, const LightField& target, Sampling sampling,
                           const CompareEyebox& eyebox) {
  EyeModel centred = model.system().eye;
  centred.pose = EyePose{};
  const std::array<double, 2> reach = PupilReachOnEyePlane(centred);
  EyeboxMapOptions o;
  o.accommodation_diopters = *eyebox.accommodation_diopters;
  o.pupil_step_m = eyebox.step_m;
  o.quality_db = eyebox.quality_db;
  const std::array<double, 2> half = {0.5 * target.geometry.eyebox_width_m, 0.5 * target.geometry.eyebox_height_m};
  for (int a = 0; a < 2; ++a)
    o.pupil_half_range_m[a] = std::floor(std::max(0.0, half[a] - reach[a]) / eyebox.step_m + 1e-9) * eyebox.step_m;
  const EyeboxMap map = MapEyebox(model, t, LightFieldRadiance(target, sampling), o);
  return {map.pupil.within(eyebox.quality_db), map.pupil.within_reaches_edge(eyebox.quality_db),
          map.pupil.centre().psnr_db};
}

}  // namespace

std::array<double, 3> CommonTargetMove(const std::vector<CompareRun>& runs) {
  std::array<double, 3> move{0, 0, 0};
  for (size_t k = 0; k < runs.size(); ++k) {
    const std::array<double, 3> m = TargetSceneMove(runs[k].system.eye);
    if (k == 0) {
      move = m;
    } else if (m != move) {
      throw Error("compare: " + runs[0].display + " and " + runs[k].display +
                  " see the target scene from different places (an eye of a binocular pair with a display of its "
                  "own sees it from its own axis): compare displays seen by the same eye");
    }
  }
  return move;
}

std::vector<CompareResult> RunComparison(const std::vector<CompareRun>& runs, const LightField& target,
                                         bool show_progress, const SolverRegistry& registry,
                                         const CompareEyebox& eyebox) {
  std::vector<CompareResult> results;
  for (const CompareRun& run : runs) {
    DisplayModel model(run.system, target.geometry, run.sampling);
    SolverOptions options = run.options;
    const std::string label = RunLabel(run.display, run.solver, options.objective);
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
                    run.system.subframes * run.system.frame_rate_hz,
                    run.options_from,
                    std::nullopt};
    r.report = registry.create(run.solver)->Solve(model, target, options, &t);
    AddFlickerCheck(model, t, &r.report);
    if (progress) progress->Finish(r.report.BriefReport());
    if (eyebox.accommodation_diopters && r.report.IsSolutionUsable())
      r.eyebox = MeasureEyebox(model, t, target, run.sampling, eyebox);
    results.push_back(std::move(r));
  }
  return results;
}

namespace {

bool AnyEyebox(const std::vector<CompareResult>& results) {
  return std::any_of(results.begin(), results.end(), [](const CompareResult& r) { return r.eyebox.has_value(); });
}

bool AnyFlicker(const std::vector<CompareResult>& results) {
  return std::any_of(results.begin(), results.end(),
                     [](const CompareResult& r) { return r.report.flicker.has_value(); });
}

// "visible 3.2 @ 60 Hz", "no 0.41", or "-" for a display of one subframe.
std::string FlickerText(const CompareResult& r) {
  if (!r.report.flicker) return "-";
  const FlickerVerdict& f = *r.report.flicker;
  char text[64];
  std::snprintf(text, sizeof text, "%s %.2g @ %.0f Hz", f.visible() ? "visible" : "no", f.visibility, f.frequency_hz);
  return text;
}

// "2.00 x >= 1.50 mm", or "-" for a run without one.
std::string EyeboxText(const CompareResult& r) {
  if (!r.eyebox) return "-";
  auto side = [&](int a) {
    return std::string(r.eyebox->reaches_edge[a] ? ">= " : "") + FormatFixed(r.eyebox->within_m[a] * 1e3, 2);
  };
  return side(0) + " x " + side(1) + " mm";
}

}  // namespace

std::string CompareTable(const std::vector<CompareResult>& results) {
  const bool with_eyebox = AnyEyebox(results);
  std::string out =
      "display                      solver                 objective   PSNR (dB)  focal stack (dB)   seconds  "
      "iterations  subframes  panel (Hz)  brightness (lum.)  brightness R G B       options  termination";
  out += with_eyebox ? "  eyebox" : "";
  const bool with_flicker = AnyFlicker(results);
  out += with_flicker ? "  flicker (visibility)     " : "";
  const std::vector<const TraceColumn*> metrics = MeasuredMetricColumns(results);
  for (const TraceColumn* c : metrics) out += "  " + MetricHeading(*c);
  out += "\n";
  for (const CompareResult& r : results) {
    const double focal_stack = FinalFocalStackPsnr(r.report);
    char line[400];
    std::snprintf(
        line, sizeof line, "%-28s %-22s %-10s %10s %17s %9.2f %11d %10d %11.0f %18.4f  %.4f %.4f %.4f   %-7s  %s\n",
        r.display.c_str(), r.solver.c_str(), r.report.objective.c_str(), Psnr(r.report.final_psnr_db).c_str(),
        std::isnan(focal_stack) ? "-" : Psnr(focal_stack).c_str(), r.report.seconds, r.report.iterations, r.subframes,
        r.panel_refresh_hz, r.luminance_efficiency, r.brightness_efficiency[0], r.brightness_efficiency[1],
        r.brightness_efficiency[2], r.options_from.c_str(), ToString(r.report.termination).c_str());
    out += line;
    if (with_eyebox) out.insert(out.size() - 1, "  " + EyeboxText(r));
    if (with_flicker) {
      char cell[48];
      std::snprintf(cell, sizeof cell, "  %-24s", FlickerText(r).c_str());
      out.insert(out.size() - 1, cell);
    }
    for (const TraceColumn* c : metrics) {
      const double v = FinalTraceValue(*c, r.report);
      char cell[40];
      std::snprintf(cell, sizeof cell, "  %*s", int(MetricHeading(*c).size()),
                    std::isnan(v) ? "-" : FormatFixed(v, std::string(c->unit) == "JND" ? 2 : 4).c_str());
      out.insert(out.size() - 1, cell);
    }
  }
  return out;
}

std::string CompareCsv(const std::vector<CompareResult>& results) {
  std::string out =
      "display,solver,objective,final_psnr_db,final_focal_stack_psnr_db,seconds,iterations,subframes,panel_refresh_hz,"
      "luminance_efficiency,efficiency_r,efficiency_g,efficiency_b,termination,solver_options";
  const bool with_eyebox = AnyEyebox(results);
  out += with_eyebox ? ",eyebox_x_mm,eyebox_y_mm,eyebox_x_reaches_edge,eyebox_y_reaches_edge" : "";
  const bool with_flicker = AnyFlicker(results);
  out += with_flicker ? ",flicker_visible,flicker_visibility,flicker_hz,flicker_modulation,flicker_worst_x_deg,"
                        "flicker_worst_y_deg,flicker_luminance_cd_m2"
                      : "";
  const std::vector<const TraceColumn*> metrics = MeasuredMetricColumns(results);
  for (const TraceColumn* c : metrics) out += std::string(",final_") + c->name;
  out += "\n";
  for (const CompareResult& r : results) {
    char line[400];
    std::snprintf(line, sizeof line, "%s,%s,%s,%s,%s,%.6f,%d,%d,%.3f,%.6f,%.6f,%.6f,%.6f,%s,%s\n", r.display.c_str(),
                  r.solver.c_str(), r.report.objective.c_str(), Psnr(r.report.final_psnr_db).c_str(),
                  PsnrField(FinalFocalStackPsnr(r.report)).c_str(), r.report.seconds, r.report.iterations, r.subframes,
                  r.panel_refresh_hz, r.luminance_efficiency, r.brightness_efficiency[0], r.brightness_efficiency[1],
                  r.brightness_efficiency[2], ToString(r.report.termination).c_str(), r.options_from.c_str());
    out += line;
    if (with_eyebox) {
      char extra[120] = ",,,,";
      if (r.eyebox)
        std::snprintf(extra, sizeof extra, ",%.4f,%.4f,%d,%d", r.eyebox->within_m[0] * 1e3, r.eyebox->within_m[1] * 1e3,
                      int(r.eyebox->reaches_edge[0]), int(r.eyebox->reaches_edge[1]));
      out.insert(out.size() - 1, extra);
    }
    if (with_flicker) {
      char extra[200] = ",,,,,,,";
      if (const std::optional<FlickerVerdict>& f = r.report.flicker)
        std::snprintf(extra, sizeof extra, ",%d,%.6g,%.3f,%.6g,%.3f,%.3f,%.6g", int(f->visible()), f->visibility,
                      f->frequency_hz, f->modulation, f->x_deg, f->y_deg, f->luminance_cd_m2);
      out.insert(out.size() - 1, extra);
    }
    for (const TraceColumn* c : metrics)
      out.insert(out.size() - 1, "," + TraceField(*c, FinalTraceValue(*c, r.report), 6, true));
  }
  return out;
}

nlohmann::json CompareJson(const std::vector<CompareResult>& results) {
  const auto number = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); };
  nlohmann::json rows = nlohmann::json::array();
  for (const CompareResult& r : results) {
    nlohmann::json row = {{"display", r.display},
                          {"solver", r.solver},
                          {"objective", r.report.objective},
                          {"final_psnr_db", number(r.report.final_psnr_db)},
                          {"final_focal_stack_psnr_db", number(FinalFocalStackPsnr(r.report))},
                          {"seconds", r.report.seconds},
                          {"iterations", r.report.iterations},
                          {"subframes", r.subframes},
                          {"panel_refresh_hz", r.panel_refresh_hz},
                          {"luminance_efficiency", r.luminance_efficiency},
                          {"efficiency_rgb", r.brightness_efficiency},
                          {"termination", ToString(r.report.termination)},
                          {"solver_options", r.options_from},
                          {"eyebox", nullptr},
                          {"flicker", nullptr}};
    if (r.eyebox) row["eyebox"] = {{"within_m", r.eyebox->within_m}, {"reaches_edge", r.eyebox->reaches_edge}};
    if (r.report.flicker) row["flicker"] = r.report.flicker->ToJson();
    for (const TraceColumn* c : MeasuredMetricColumns(results))
      row[std::string("final_") + c->name] = number(FinalTraceValue(*c, r.report));
    rows.push_back(row);
  }
  return rows;
}

std::string TracesCsv(const std::vector<CompareResult>& results) {
  // `objective` is the value the run minimized, of the objective named in `objective_kind`.
  // Every column (a focal-stack metric's where some run measured it), each run's unmeasured ones empty, so that
  // the runs share one header.
  const std::vector<const TraceColumn*> metrics = MeasuredMetricColumns(results);
  std::vector<const TraceColumn*> columns;
  for (const TraceColumn& c : TraceColumns())
    if (c.kind != TraceValueKind::kScore || std::find(metrics.begin(), metrics.end(), &c) != metrics.end())
      columns.push_back(&c);
  std::string out = "display,solver,objective_kind";
  for (const TraceColumn* c : columns) out += std::string(",") + c->name;
  out += "\n";
  for (const CompareResult& r : results)
    for (const IterationRecord& row : r.report.trace) {
      out += r.display + "," + r.solver + "," + r.report.objective;
      for (const TraceColumn* c : columns) out += "," + TraceField(*c, c->value(row), 3, c->measured_only);
      out += "\n";
    }
  return out;
}

namespace {

// One panel of a trace column against wall time, read by `db` (a PSNR, or with `score` a metric whose axis is
// padded by a tenth of its range instead of rounded to whole dB); no line for a run without a finite value.
PlotPanel PsnrPanel(const std::vector<CompareResult>& results, const std::string& title,
                    double (*db)(const IterationRecord&), const std::string& y_label = "PSNR (dB)",
                    bool score = false) {
  static const char* kColors[] = {"#d62728", "#1f77b4", "#2ca02c", "#ff7f0e",
                                  "#9467bd", "#8c564b", "#e377c2", "#17becf"};
  PlotPanel panel;
  panel.title = title;
  panel.x_label = "wall time (s)";
  panel.y_label = y_label;
  double t_max = 0, y_min = INFINITY, y_max = -INFINITY;
  for (size_t k = 0; k < results.size(); ++k) {
    PlotLine line{RunLabel(results[k]), kColors[k % 8], k >= 8, {}, {}};
    for (const IterationRecord& row : results[k].report.trace) {
      if (!std::isfinite(db(row))) continue;
      line.x.push_back(row.seconds);
      line.y.push_back(db(row));
      t_max = std::max(t_max, row.seconds);
      y_min = std::min(y_min, db(row));  // iteration 0 too: the curve is seen from where it starts
      y_max = std::max(y_max, db(row));
    }
    if (!line.x.empty()) panel.lines.push_back(std::move(line));
  }
  if (!std::isfinite(y_min)) y_min = 0, y_max = 1;
  panel.x_max = t_max > 0 ? t_max * 1.02 : 1;
  if (score) {
    const double pad = std::max(0.1 * (y_max - y_min), 1e-3 * std::max(1.0, std::abs(y_max)));
    panel.y_min = y_min - pad, panel.y_max = y_max + pad;
    return panel;
  }
  panel.y_min = std::floor(y_min - 0.5);
  panel.y_max = std::ceil(y_max + 0.5);
  return panel;
}

}  // namespace

std::string PsnrAgainstTimeSvg(const std::vector<CompareResult>& results) {
  std::vector<PlotPanel> panels = {
      PsnrPanel(results, "light-field PSNR against wall time", [](const IterationRecord& r) { return r.psnr_db; })};
  PlotPanel focal = PsnrPanel(results, "focal-stack PSNR against wall time (mean over accommodation states)",
                              [](const IterationRecord& r) { return r.focal_stack_psnr_db; });
  if (!focal.lines.empty()) panels.push_back(std::move(focal));
  for (const TraceColumn* c : MeasuredMetricColumns(results)) {
    const std::string heading = MetricHeading(*c);
    PlotPanel panel =
        PsnrPanel(results,
                  "focal-stack " + heading + " against wall time (mean over accommodation states; " +
                      (c->kind == TraceValueKind::kScore && std::string(c->unit) == "JND" ? "lower is better)"
                                                                                          : "higher is better)"),
                  c->value, heading, true);
    if (!panel.lines.empty()) panels.push_back(std::move(panel));
  }
  return RenderSvg(panels, static_cast<int>(panels.size()), "");
}

}  // namespace layerlab
