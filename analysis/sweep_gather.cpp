#include "layerlab/analysis/sweep_gather.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>

#include "layerlab/analysis/svg_plot.h"
#include "layerlab/framework/atomic_file.h"
#include "layerlab/framework/csv_cell.h"
#include "layerlab/framework/staged_output.h"

namespace layerlab {
namespace {

namespace fs = std::filesystem;

const char* const kColors[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#17becf"};

std::string Cell(const nlohmann::json& v) {
  if (v.is_null()) return "";
  if (v.is_string()) return v.get<std::string>();
  if (v.is_number_float()) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", v.get<double>());
    return buf;
  }
  return v.dump();
}

std::string Slug(const std::string& text) {
  std::string s;
  for (char c : text) {
    if (std::isalnum(static_cast<unsigned char>(c)))
      s += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    else if (!s.empty() && s.back() != '_')
      s += '_';
  }
  while (!s.empty() && s.back() == '_') s.pop_back();
  return s.empty() ? "result" : s;
}

// " D" of "peak accommodation, 0.7 D, 2 cpd (D)": the unit in the column's last parentheses.
std::string UnitOf(const std::string& column) {
  const size_t open = column.rfind('('), close = column.rfind(')');
  if (open == std::string::npos || close != column.size() - 1 || close == open + 1) return "";
  return " " + column.substr(open + 1, close - open - 1);
}

struct Row {
  const SweepJob* job;
  SweepJobState state;
};

// One panel: `column` against the first numeric parameter (or the job index), a line per other combination.
PlotPanel Panel(const SweepSpec& spec, const std::vector<Row>& rows, const std::string& column, bool* varies) {
  PlotPanel panel;
  panel.title = column;
  panel.y_label = column;
  int x_param = -1;
  for (size_t k = 0; k < spec.parameters.size(); ++k)
    if (!spec.parameters[k].numbers.empty() && spec.parameters[k].values.size() > 1) {
      x_param = static_cast<int>(k);
      break;
    }
  panel.x_label = x_param >= 0 ? spec.parameters[x_param].column() : "job";
  std::map<std::string, PlotLine> lines;  // by the other parameters' labels
  std::vector<std::string> order;
  std::set<double> ideals;
  double x_lo = INFINITY, x_hi = -INFINITY, y_lo = INFINITY, y_hi = -INFINITY;
  for (const Row& row : rows) {
    if (!row.state.complete) continue;
    auto it = std::find_if(row.state.results.begin(), row.state.results.end(),
                           [&](const SweepResult& r) { return r.column == column; });
    if (it == row.state.results.end() || !it->value.is_number()) continue;
    std::string key;
    for (size_t k = 0; k < spec.parameters.size(); ++k) {
      if (static_cast<int>(k) == x_param || spec.parameters[k].values.size() < 2) continue;
      key += (key.empty() ? "" : ", ") + spec.parameters[k].name + " " + spec.parameters[k].labels[row.job->choice[k]];
    }
    if (!lines.count(key)) order.push_back(key);
    PlotLine& line = lines[key];
    const double x =
        x_param >= 0 ? spec.parameters[x_param].numbers[row.job->choice[x_param]] : static_cast<double>(row.job->index);
    const double y = it->value.get<double>();
    line.x.push_back(x);
    line.y.push_back(y);
    x_lo = std::min(x_lo, x), x_hi = std::max(x_hi, x), y_lo = std::min(y_lo, y), y_hi = std::max(y_hi, y);
    if (it->ideal) ideals.insert(*it->ideal);
  }
  *varies = std::isfinite(y_lo) && y_hi > y_lo;
  for (double ideal : ideals) {
    panel.levels.push_back({ideal, "target depth " + Cell(ideal) + UnitOf(column)});
    y_lo = std::min(y_lo, ideal), y_hi = std::max(y_hi, ideal);
  }
  for (size_t i = 0; i < order.size(); ++i) {
    PlotLine line = lines[order[i]];
    line.label = order[i].empty() ? column : order[i];
    line.color = kColors[i % std::size(kColors)];
    line.dashed = (i / std::size(kColors)) % 2 == 1;
    panel.lines.push_back(line);
  }
  if (!std::isfinite(x_lo)) x_lo = 0, x_hi = 1, y_lo = 0, y_hi = 1;
  if (x_hi <= x_lo) x_lo -= 0.5, x_hi += 0.5;
  const double pad = y_hi > y_lo ? 0.08 * (y_hi - y_lo) : std::max(1e-3, 0.05 * std::fabs(y_hi));
  panel.x_min = x_lo, panel.x_max = x_hi, panel.y_min = y_lo - pad, panel.y_max = y_hi + pad;
  return panel;
}

// The table: a header and one line of cells per job.
struct SweepTable {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> cells;
};

SweepTable TableOf(const SweepSpec& spec, const std::vector<Row>& rows, const std::vector<std::string>& columns) {
  SweepTable table;
  table.header = {"job"};
  for (const SweepParameter& p : spec.parameters) table.header.push_back(p.column());
  table.header.insert(table.header.end(), {"state", "runner", "job time (s)"});
  table.header.insert(table.header.end(), columns.begin(), columns.end());
  for (const Row& row : rows) {
    std::vector<std::string> line = {row.job->id};
    for (size_t k = 0; k < spec.parameters.size(); ++k) {
      const SweepParameter& p = spec.parameters[k];
      line.push_back(p.numbers.empty() ? p.labels[row.job->choice[k]] : Cell(p.numbers[row.job->choice[k]]));
    }
    const SweepJobState& s = row.state;
    line.push_back(s.complete ? "complete" : s.failed ? "failed" : "not run");
    line.push_back(s.runner);
    line.push_back(s.complete || s.failed ? Cell(s.seconds) : "");
    for (const std::string& c : columns) {
      auto it = std::find_if(s.results.begin(), s.results.end(), [&](const SweepResult& r) { return r.column == c; });
      line.push_back(it == s.results.end() ? "" : Cell(it->value));
    }
    table.cells.push_back(line);
  }
  return table;
}

std::string TableCsv(const SweepTable& table) {
  std::ostringstream csv;
  for (size_t i = 0; i < table.header.size(); ++i) csv << (i ? "," : "") << CsvCell(table.header[i]);
  csv << "\n";
  for (const auto& line : table.cells) {
    for (size_t i = 0; i < line.size(); ++i) csv << (i ? "," : "") << CsvCell(line[i]);
    csv << "\n";
  }
  return csv.str();
}

// A plot per result column that varies across the jobs; the files written, under `staging`.
std::vector<std::string> WritePlots(const SweepSpec& spec, const std::vector<Row>& rows,
                                    const std::vector<std::string>& columns, const fs::path& staging) {
  std::vector<std::string> plots;
  fs::create_directories(staging / "plots");
  for (const std::string& c : columns) {
    bool varies = false;
    const PlotPanel panel = Panel(spec, rows, c, &varies);
    if (!varies) continue;  // the same in every job (the iteration count): a column, not a plot
    const std::string file = "plots/" + Slug(c) + ".svg";
    WriteFileAtomically((staging / file).string(), RenderSvg({panel}, 1, spec.name + ": " + c));
    plots.push_back(file);
  }
  return plots;
}

std::string TableHtml(const SweepSpec& spec, size_t jobs, const SweepSummary& summary, const SweepTable& table,
                      const std::vector<Row>& rows, const std::vector<std::string>& plots) {
  std::ostringstream html;
  html << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>" << Escape(spec.name)
       << "</title>\n<style>body{font-family:sans-serif;margin:2em}table{border-collapse:collapse}"
          "td,th{border:1px solid #ccc;padding:3px 8px;text-align:right}th{background:#eee}"
          "tr.failed td{background:#fdd}img{max-width:48%;margin:4px}</style></head><body>\n";
  html << "<h1>" << Escape(spec.name) << "</h1>\n";
  if (!spec.description.empty()) html << "<p>" << Escape(spec.description) << "</p>\n";
  html << "<p>" << jobs << " jobs: " << summary.complete << " complete, " << summary.failed << " failed, "
       << summary.pending << " not run. Base scene <code>" << Escape(spec.scene) << "</code>; work: ";
  for (size_t i = 0; i < spec.work().size(); ++i) html << (i ? ", " : "") << spec.work()[i];
  html << ". <a href=\"table.csv\">table.csv</a></p>\n<table>\n<tr>";
  for (const std::string& h : table.header) html << "<th>" << Escape(h) << "</th>";
  html << "</tr>\n";
  for (size_t r = 0; r < table.cells.size(); ++r) {
    html << "<tr" << (rows[r].state.failed ? " class=\"failed\"" : "") << ">";
    for (size_t i = 0; i < table.cells[r].size(); ++i) {
      if (i == 0 && rows[r].state.complete)
        html << "<td><a href=\"jobs/" << table.cells[r][0] << "/out/index.html\">" << table.cells[r][0] << "</a></td>";
      else
        html << "<td>" << Escape(table.cells[r][i]) << "</td>";
    }
    html << "</tr>\n";
  }
  html << "</table>\n";
  for (const Row& row : rows)
    if (row.state.failed)
      html << "<p>job " << row.job->id << " failed: <code>" << Escape(row.state.error) << "</code></p>\n";
  for (const std::string& p : plots) html << "<img src=\"" << p << "\" alt=\"" << Escape(p) << "\">\n";
  html << "</body></html>\n";
  return html.str();
}

}  // namespace

SweepSummary GatherSweep(const SweepSpec& spec, const std::vector<SweepJob>& jobs, const std::string& out) {
  SweepSummary summary;
  std::vector<Row> rows;
  std::vector<std::string> columns;  // the results', in first-seen order
  for (const SweepJob& job : jobs) {
    rows.push_back({&job, ReadJobState(out, job)});
    const SweepJobState& s = rows.back().state;
    (s.complete ? summary.complete : s.failed ? summary.failed : summary.pending)++;
    for (const SweepResult& r : s.results)
      if (std::find(columns.begin(), columns.end(), r.column) == columns.end()) columns.push_back(r.column);
  }
  const SweepTable table = TableOf(spec, rows, columns);

  StagedOutput stage(out, "sweep", {"table.csv", "table.html", "plots"},
                     {{spec.file, "the sweep file"}, {spec.scene, "the base scene"}});
  const fs::path staging = stage.staging();
  try {
    WriteFileAtomically((staging / "table.csv").string(), TableCsv(table));
    const std::vector<std::string> plots = WritePlots(spec, rows, columns, staging);
    WriteFileAtomically((staging / "table.html").string(), TableHtml(spec, jobs.size(), summary, table, rows, plots));
  } catch (const Error& e) {
    throw stage.Explain(e);
  }
  summary.written = stage.Commit().written;
  return summary;
}

}  // namespace layerlab
