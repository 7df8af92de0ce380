#include "layerlab/design/design_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "layerlab/analysis/svg_plot.h"
#include "layerlab/design/design_starts.h"
#include "layerlab/framework/atomic_file.h"
#include "layerlab/framework/csv_cell.h"
#include "layerlab/framework/staged_output.h"
#include "layerlab/systems/scene_document.h"

namespace layerlab {
namespace {

namespace fs = std::filesystem;

std::string Cell(double v) {
  if (!std::isfinite(v)) return "";
  char text[32];
  std::snprintf(text, sizeof text, "%.8g", v);
  return text;
}

struct Track {  // the history in evaluation order, with the best so far
  std::vector<const DesignEvaluation*> rows;
  std::vector<double> best_so_far, elapsed;  // shown objective; cumulative evaluation time (s)
};

Track TrackOf(const DesignSpec& spec, const DesignHistory& history) {
  Track t;
  t.rows = history.evaluations;
  double best_loss = INFINITY, best_shown = NAN, clock = 0;
  for (const DesignEvaluation* e : t.rows) {
    clock += e->seconds;
    if (MeetsConstraints(spec, *e) && e->loss < best_loss) best_loss = e->loss, best_shown = ShownObjective(spec, *e);
    t.best_so_far.push_back(best_shown);
    t.elapsed.push_back(clock);
  }
  return t;
}

std::string HistoryCsv(const DesignSpec& spec, const Track& t) {
  const bool multistart = spec.optimizer.global == "multistart";
  std::vector<std::string> header = {"evaluation", "job"};
  if (multistart) header.push_back("start");
  for (const DesignVariable& v : spec.variables) header.push_back(v.column());
  header.insert(header.end(), {"state", "error", "warm start from"});
  for (const DesignMetric& m : spec.metrics) header.push_back(m.column());
  header.insert(header.end(), {"objective: " + spec.objective_column(), "best so far: " + spec.objective_column(),
                               "evaluation time (s)", "cumulative time (s)"});
  std::ostringstream csv;
  for (size_t i = 0; i < header.size(); ++i) csv << (i ? "," : "") << CsvCell(header[i]);
  csv << "\n";
  for (size_t r = 0; r < t.rows.size(); ++r) {
    const DesignEvaluation& e = *t.rows[r];
    std::vector<std::string> line = {std::to_string(e.index), e.id};
    if (multistart) line.push_back(e.start);
    for (double x : e.x) line.push_back(Cell(x));
    line.push_back(e.failed ? "failed" : "complete");
    line.push_back(e.error);
    line.push_back(e.warm_start);
    for (size_t m = 0; m < spec.metrics.size(); ++m) line.push_back(e.failed ? "" : Cell(e.metrics[m]));
    line.push_back(e.failed ? "" : Cell(ShownObjective(spec, e)));
    line.push_back(Cell(t.best_so_far[r]));
    line.push_back(Cell(e.seconds));
    line.push_back(Cell(t.elapsed[r]));
    for (size_t i = 0; i < line.size(); ++i) csv << (i ? "," : "") << CsvCell(line[i]);
    csv << "\n";
  }
  return csv.str();
}

void FitY(PlotPanel* p) {
  double lo = INFINITY, hi = -INFINITY;
  for (const PlotLine& l : p->lines)
    for (double y : l.y)
      if (std::isfinite(y)) lo = std::min(lo, y), hi = std::max(hi, y);
  if (!std::isfinite(lo)) lo = 0, hi = 1;
  const double pad = hi > lo ? 0.08 * (hi - lo) : std::max(1e-3, 0.05 * std::abs(hi));
  p->y_min = lo - pad, p->y_max = hi + pad;
}

std::string ConvergenceSvg(const DesignSpec& spec, const Track& t) {
  const std::string objective = spec.objective_column();
  std::vector<PlotPanel> panels(2);
  for (int k = 0; k < 2; ++k) {
    PlotPanel& p = panels[k];
    p.title = k == 0 ? "against evaluations" : "against evaluation time";
    p.x_label =
        k == 0 ? (spec.optimizer.global == "multistart" ? "evaluation (the starts one after another)" : "evaluation")
               : "cumulative evaluation time (s)";
    p.y_label = objective;
    PlotLine each, best;
    each.label = "each evaluation", each.color = "#999999", each.points_only = true;
    best.label = "best so far", best.color = "#1f77b4";
    for (size_t r = 0; r < t.rows.size(); ++r) {
      const double x = k == 0 ? static_cast<double>(r) : t.elapsed[r];
      if (!t.rows[r]->failed) {
        each.x.push_back(x);
        each.y.push_back(ShownObjective(spec, *t.rows[r]));
      }
      best.x.push_back(x);
      best.y.push_back(t.best_so_far[r]);
    }
    p.x_min = 0;
    p.x_max = std::max(1.0, best.x.empty() ? 1.0 : best.x.back());
    p.lines = {best, each};
    FitY(&p);
  }
  return RenderSvg(panels, 2, spec.name + ": " + objective);
}

// One variable: the objective over it. Two: the evaluated designs over both, in four bands of the objective.
std::string SurfaceSvg(const DesignSpec& spec, const Track& t, const DesignEvaluation* best) {
  PlotPanel p;
  const DesignVariable& v0 = spec.variables[0];
  p.x_label = v0.column();
  p.x_min = v0.min, p.x_max = v0.max;
  std::vector<const DesignEvaluation*> ok;
  for (const DesignEvaluation* e : t.rows)
    if (!e->failed) ok.push_back(e);
  if (spec.variables.size() == 1) {
    std::sort(ok.begin(), ok.end(), [](auto* a, auto* b) { return a->x[0] < b->x[0]; });
    PlotLine line;
    line.label = "evaluations", line.color = "#1f77b4";
    for (const DesignEvaluation* e : ok) line.x.push_back(e->x[0]), line.y.push_back(ShownObjective(spec, *e));
    p.y_label = spec.objective_column();
    p.lines = {line};
    if (best) p.markers.push_back({best->x[0], "best " + Cell(best->x[0]) + (v0.unit.empty() ? "" : " " + v0.unit)});
    FitY(&p);
    return RenderSvg({p}, 1, spec.name + ": " + spec.objective_column() + " over " + v0.name);
  }
  const DesignVariable& v1 = spec.variables[1];
  p.y_label = v1.column();
  p.y_min = v1.min, p.y_max = v1.max;
  std::vector<double> shown;
  for (const DesignEvaluation* e : ok) shown.push_back(ShownObjective(spec, *e));
  std::vector<double> sorted = shown;
  std::sort(sorted.begin(), sorted.end());
  const char* colors[] = {"#d62728", "#ff7f0e", "#2ca02c", "#1f77b4"};  // worst to best quarter
  const bool higher = spec.objective.size() == 1 && spec.metrics[spec.objective[0].metric].higher_is_better;
  for (int q = 0; q < 4 && !sorted.empty(); ++q) {
    const size_t a = sorted.size() * q / 4, b = std::max(a + 1, sorted.size() * (q + 1) / 4) - 1;
    const double lo = higher ? sorted[a] : sorted[sorted.size() - 1 - b];
    const double hi = higher ? sorted[b] : sorted[sorted.size() - 1 - a];
    PlotLine band;
    band.label = spec.objective_column() + " " + Cell(lo) + " to " + Cell(hi);
    band.color = colors[q];
    band.points_only = true;
    for (size_t i = 0; i < ok.size(); ++i)
      if (shown[i] >= lo && shown[i] <= hi) band.x.push_back(ok[i]->x[0]), band.y.push_back(ok[i]->x[1]);
    if (!band.x.empty()) p.lines.push_back(band);
  }
  if (best) p.markers.push_back({best->x[0], "best"});
  return RenderSvg({p}, 1, spec.name + ": the evaluated designs, by " + spec.objective_column());
}

// A multistart's starts: where each began, its evaluations and its best design.
void StartsTable(const DesignSpec& spec, const Track& t, std::ostringstream& h) {
  h << "<h2>Starts</h2>\n<table>\n<tr><th>start</th>";
  for (const DesignVariable& v : spec.variables) h << "<th>from: " << Escape(v.column()) << "</th>";
  h << "<th>evaluations</th><th>best: " << Escape(spec.objective_column()) << "</th><th>at</th></tr>\n";
  const std::vector<std::vector<double>> points = MultistartPoints(spec);
  std::vector<std::string> order;
  for (const DesignEvaluation* e : t.rows)
    if (std::find(order.begin(), order.end(), e->start) == order.end()) order.push_back(e->start);
  for (const std::string& id : order) {
    std::vector<const DesignEvaluation*> own;
    for (const DesignEvaluation* e : t.rows)
      if (e->start == id) own.push_back(e);
    const DesignEvaluation* best = BestFeasible(spec, own);
    h << "<tr><th>" << Escape(id) << "</th>";
    const size_t k = static_cast<size_t>(std::stoi(id.substr(1)));  // "s07"
    for (double x : points[k]) h << "<td>" << Cell(x) << "</td>";
    h << "<td>" << own.size() << "</td><td>" << (best ? Cell(ShownObjective(spec, *best)) : "none feasible")
      << "</td><td>" << (best ? Escape(best->id) : "") << "</td></tr>\n";
  }
  h << "</table>\n";
}

std::string ReportHtml(const DesignSpec& spec, const DesignEvaluator& evaluator, const DesignHistory& history,
                       const Track& track, const DesignSearch& search, const DesignEvaluation* start,
                       const DesignEvaluation* best, bool surface) {
  std::ostringstream h;
  h << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>" << Escape(spec.name)
    << "</title>\n<style>body{font-family:sans-serif;margin:2em}table{border-collapse:collapse}"
       "td,th{border:1px solid #ccc;padding:3px "
       "8px;text-align:right}th{background:#eee}img{max-width:48%;margin:4px}img.wide{max-width:96%}"
       "</style></head><body>\n<h1>"
    << Escape(spec.name) << "</h1>\n";
  if (!spec.description.empty()) h << "<p>" << Escape(spec.description) << "</p>\n";
  h << "<p>Base scene <code>" << Escape(spec.scene) << "</code>; " << history.evaluations.size() << " evaluations ("
    << history.ran << " run by this command, " << history.replayed
    << " read back from its log). The search ended because " << Escape(search.stopped) << ".</p>\n";
  auto link = [&](const DesignEvaluation& e) {
    std::string cells;
    for (const SweepJob& job : evaluator.JobsOf(e))
      cells += "<a href=\"jobs/" + job.id + "/out/index.html\">" + job.id + "</a> ";
    return cells;
  };
  h << "<table>\n<tr><th></th><th>start</th><th>optimized</th></tr>\n";
  const auto row = [&](const std::string& name, auto value) {
    h << "<tr><th>" << Escape(name) << "</th><td>" << (start ? value(*start) : "") << "</td><td>"
      << (best ? value(*best) : "no design met the constraints") << "</td></tr>\n";
  };
  for (size_t k = 0; k < spec.variables.size(); ++k)
    row(spec.variables[k].column(), [&](const DesignEvaluation& e) { return Cell(e.x[k]); });
  for (size_t m = 0; m < spec.metrics.size(); ++m)
    row(spec.metrics[m].column(), [&](const DesignEvaluation& e) { return e.failed ? "failed" : Cell(e.metrics[m]); });
  row("objective: " + spec.objective_column(),
      [&](const DesignEvaluation& e) { return e.failed ? std::string("failed") : Cell(ShownObjective(spec, e)); });
  row("run (report)", link);
  h << "</table>\n";
  if (start && start->failed) h << "<p>The start failed: <code>" << Escape(start->error) << "</code></p>\n";
  if (spec.optimizer.global == "multistart" && !track.rows.empty()) StartsTable(spec, track, h);
  h << "<p><a href=\"history.csv\">history.csv</a>";
  if (best) h << " · <a href=\"best_scene.json\">best_scene.json</a> (<code>layerlab run best_scene.json</code>)";
  h << "</p>\n<img class=\"wide\" src=\"convergence.svg\" alt=\"convergence\">\n";
  if (surface) h << "<img src=\"surface.svg\" alt=\"objective over the variables\">\n";
  h << "</body></html>\n";
  return h.str();
}

}  // namespace

double ShownObjective(const DesignSpec& spec, const DesignEvaluation& e) {
  if (spec.objective.size() == 1) return e.metrics[spec.objective[0].metric];
  return e.loss;
}

std::vector<std::string> WriteDesignReport(const DesignSpec& spec, const DesignEvaluator& evaluator,
                                           const DesignHistory& history, const DesignSearch& search,
                                           const DesignEvaluation* best, const std::string& out) {
  const Track track = TrackOf(spec, history);
  const DesignEvaluation* start = track.rows.empty() ? nullptr : track.rows.front();
  for (const DesignEvaluation* e : track.rows) {
    std::vector<double> x0;
    for (const DesignVariable& v : spec.variables) x0.push_back(v.start);
    if (e->x == x0) start = e;
  }
  const bool surface = spec.variables.size() <= 2;
  StagedOutput stage(out, "optimize",
                     {"best_scene.json", "history.csv", "convergence.svg", "surface.svg", "report.html"},
                     {{spec.file, "the design file"}, {spec.scene, "the base scene"}});
  const fs::path staging = stage.staging();
  try {
    WriteFileAtomically((staging / "history.csv").string(), HistoryCsv(spec, track));
    WriteFileAtomically((staging / "convergence.svg").string(), ConvergenceSvg(spec, track));
    if (surface) WriteFileAtomically((staging / "surface.svg").string(), SurfaceSvg(spec, track, best));
    if (best) {
      nlohmann::ordered_json scene = evaluator.SceneWith(best->x);
      std::string values;
      for (size_t k = 0; k < spec.variables.size(); ++k)
        values += (k ? ", " : "") + spec.variables[k].name + " = " + Cell(best->x[k]) +
                  (spec.variables[k].unit.empty() ? "" : " " + spec.variables[k].unit);
      scene["description"] = "The best design found by layerlab optimize " + spec.file + " (evaluation " + best->id +
                             "): the scene " + spec.scene + " with " + values;
      const std::string path = (fs::path(out) / "best_scene.json").string();
      RebaseRelativePaths(scene, spec.scene, path);
      WriteFileAtomically((staging / "best_scene.json").string(), scene.dump(2) + "\n");
    }
    WriteFileAtomically((staging / "report.html").string(),
                        ReportHtml(spec, evaluator, history, track, search, start, best, surface));
  } catch (const Error& e) {
    throw stage.Explain(e);
  }
  return stage.Commit().written;
}

}  // namespace layerlab
