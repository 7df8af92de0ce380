#include "layerlab/analysis/svg_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace layerlab {
std::string Escape(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '<')
      out += "&lt;";
    else if (c == '>')
      out += "&gt;";
    else if (c == '&')
      out += "&amp;";
    else if (c == '"')
      out += "&quot;";
    else
      out += c;
  }
  return out;
}

namespace {

std::string Num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f", v);
  return buf;
}

std::string TickLabel(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", std::abs(v) < 1e-12 ? 0.0 : v);
  return buf;
}

}  // namespace

std::vector<double> NiceTicks(double lo, double hi, int target_count) {
  double span = hi - lo;
  if (!(span > 0)) return {lo};
  double raw = span / std::max(1, target_count);
  double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  double step = magnitude;
  for (double m : {1.0, 2.0, 2.5, 5.0, 10.0})
    if (m * magnitude >= raw) {
      step = m * magnitude;
      break;
    }
  std::vector<double> ticks;
  for (double t = std::ceil(lo / step - 1e-9) * step; t <= hi + 1e-9 * step; t += step) ticks.push_back(t);
  return ticks;
}

namespace {

// The legend's entries: the first panel's lines, then a block for the panels' markers and one for their
// levels (each labelled as the first panel that has one).
struct LegendItem {
  enum Kind { kLine, kMarker, kLevel } kind;
  size_t line;  // kLine: the first panel's line
  std::string label;
};

std::vector<LegendItem> LegendItems(const std::vector<PlotPanel>& panels) {
  std::vector<LegendItem> items;
  if (panels.empty()) return items;
  for (size_t k = 0; k < panels.front().lines.size(); ++k)
    items.push_back({LegendItem::kLine, k, panels.front().lines[k].label});
  for (const PlotPanel& panel : panels)
    if (!panel.markers.empty()) {
      items.push_back({LegendItem::kMarker, 0, panel.markers[0].label});
      break;
    }
  for (const PlotPanel& panel : panels)
    if (!panel.levels.empty()) {
      items.push_back({LegendItem::kLevel, 0, panel.levels[0].label});
      break;
    }
  return items;
}

struct LegendEntry {
  double x;
  int row;
};

// Where each legend item goes, wrapped into rows that fit the page.
std::vector<LegendEntry> LayOutLegend(const std::vector<LegendItem>& items, double page_w, int* legend_rows) {
  std::vector<LegendEntry> legend;
  *legend_rows = items.empty() ? 0 : 1;
  double x = 20;
  for (const LegendItem& item : items) {
    double width = 44 + 7 * item.label.size();
    if (x > 20 && x + width > page_w - 8) x = 20, ++*legend_rows;
    legend.push_back({x, *legend_rows - 1});
    x += width;
  }
  return legend;
}

// Where a panel's plot area lies on the page: x0..x1 left to right, y0 (bottom) to y1 (top).
struct PlotArea {
  double ox, oy, x0, x1, y0, y1;
};

// The grid, ticks, frame and axis labels of a panel.
std::string AxesSvg(const PlotPanel& panel, const PlotArea& a) {
  const double x0 = a.x0, x1 = a.x1, y0 = a.y0, y1 = a.y1;
  auto X = [&](double x) { return x0 + (x - panel.x_min) / (panel.x_max - panel.x_min) * (x1 - x0); };
  auto Y = [&](double y) { return y0 - (y - panel.y_min) / (panel.y_max - panel.y_min) * (y0 - y1); };
  std::string svg;
  for (double t : NiceTicks(panel.x_min, panel.x_max, 6)) {
    svg += "<line x1=\"" + Num(X(t)) + "\" y1=\"" + Num(y0) + "\" x2=\"" + Num(X(t)) + "\" y2=\"" + Num(y1) +
           "\" stroke=\"#eee\"/>\n";
    svg +=
        "<text x=\"" + Num(X(t)) + "\" y=\"" + Num(y0 + 14) + "\" text-anchor=\"middle\">" + TickLabel(t) + "</text>\n";
  }
  for (double t : NiceTicks(panel.y_min, panel.y_max, 5)) {
    svg += "<line x1=\"" + Num(x0) + "\" y1=\"" + Num(Y(t)) + "\" x2=\"" + Num(x1) + "\" y2=\"" + Num(Y(t)) +
           "\" stroke=\"#eee\"/>\n";
    svg +=
        "<text x=\"" + Num(x0 - 5) + "\" y=\"" + Num(Y(t) + 4) + "\" text-anchor=\"end\">" + TickLabel(t) + "</text>\n";
  }
  svg += "<rect x=\"" + Num(x0) + "\" y=\"" + Num(y1) + "\" width=\"" + Num(x1 - x0) + "\" height=\"" + Num(y0 - y1) +
         "\" fill=\"none\" stroke=\"#333\"/>\n";
  svg += "<text x=\"" + Num((x0 + x1) / 2) + "\" y=\"" + Num(y0 + 32) + "\" text-anchor=\"middle\">" +
         Escape(panel.x_label) + "</text>\n";
  svg += "<text transform=\"translate(" + Num(a.ox + 16) + "," + Num((y0 + y1) / 2) +
         ") rotate(-90)\" text-anchor=\"middle\">" + Escape(panel.y_label) + "</text>\n";
  return svg;
}

// Line k's point symbol at (x, y): a circle, square, triangle or diamond, hollow, so that lines that
// coincide stay apart by their symbols.
std::string Symbol(size_t k, double x, double y, const std::string& color) {
  const std::string style = "\" fill=\"white\" stroke=\"" + color + "\" stroke-width=\"1.5\"/>\n";
  switch (k % 4) {
    case 0:
      return "<circle cx=\"" + Num(x) + "\" cy=\"" + Num(y) + "\" r=\"3.2" + style;
    case 1:
      return "<rect x=\"" + Num(x - 3) + "\" y=\"" + Num(y - 3) + "\" width=\"6\" height=\"6" + style;
    case 2:
      return "<polygon points=\"" + Num(x) + "," + Num(y - 4) + " " + Num(x + 3.6) + "," + Num(y + 2.6) + " " +
             Num(x - 3.6) + "," + Num(y + 2.6) + style;
    default:
      return "<polygon points=\"" + Num(x) + "," + Num(y - 4) + " " + Num(x + 4) + "," + Num(y) + " " + Num(x) + "," +
             Num(y + 4) + " " + Num(x - 4) + "," + Num(y) + style;
  }
}

// Which points of an n-point line carry a symbol: every one up to kAllSymbols points, else about
// kSymbols evenly spaced, each line starting at its own phase so that coinciding lines do not hide
// each other's.
constexpr size_t kAllSymbols = 40, kSymbols = 16;
bool CarriesSymbol(size_t point, size_t n, size_t line) {
  if (n <= kAllSymbols) return true;
  const size_t every = n / kSymbols;
  return point % every == (line * every / 4) % every;
}

// A panel's markers, levels and lines.
std::string DataSvg(const PlotPanel& panel, const PlotArea& a) {
  const double x0 = a.x0, x1 = a.x1, y0 = a.y0, y1 = a.y1;
  auto X = [&](double x) { return x0 + (x - panel.x_min) / (panel.x_max - panel.x_min) * (x1 - x0); };
  auto Y = [&](double y) { return y0 - (y - panel.y_min) / (panel.y_max - panel.y_min) * (y0 - y1); };
  std::string svg;
  std::string labels;  // over the lines, each on a white halo, so that a line does not hide it
  const std::string label_style =
      "fill=\"#555\" font-size=\"11\" stroke=\"white\" stroke-width=\"3\" paint-order=\"stroke\"";
  for (const PlotMarker& m : panel.markers) {
    svg += "<rect x=\"" + Num(X(m.x) - 5) + "\" y=\"" + Num(y1) + "\" width=\"10\" height=\"" + Num(y0 - y1) +
           "\" fill=\"#888\" fill-opacity=\"0.22\"><title>" + Escape(m.label) + "</title></rect>\n";
    labels += "<text x=\"" + Num(X(m.x) + 8) + "\" y=\"" + Num(y0 - 6) + "\" " + label_style + ">" + Escape(m.label) +
              "</text>\n";
  }
  for (const PlotLevel& l : panel.levels) {
    svg += "<rect x=\"" + Num(x0) + "\" y=\"" + Num(Y(l.y) - 4) + "\" width=\"" + Num(x1 - x0) +
           "\" height=\"8\" fill=\"#888\" fill-opacity=\"0.22\"><title>" + Escape(l.label) + "</title></rect>\n";
    labels += "<text x=\"" + Num(x1 - 6) + "\" y=\"" + Num(Y(l.y) - 7) + "\" text-anchor=\"end\" " + label_style + ">" +
              Escape(l.label) + "</text>\n";
  }
  for (const PlotLine& line : panel.lines) {
    if (line.points_only) continue;
    std::string points;
    for (size_t k = 0; k < line.x.size(); ++k) {
      if (!std::isfinite(line.y[k])) continue;
      double y = std::clamp(line.y[k], panel.y_min, panel.y_max);
      points += Num(X(line.x[k])) + "," + Num(Y(y)) + " ";
    }
    svg += "<polyline fill=\"none\" stroke=\"" + line.color + "\" stroke-width=\"2.2\"" +
           (line.dashed ? " stroke-dasharray=\"6,3\"" : "") + " points=\"" + points + "\"><title>" +
           Escape(line.label) + "</title></polyline>\n";
  }
  for (size_t l = 0; l < panel.lines.size(); ++l) {
    const PlotLine& line = panel.lines[l];
    for (size_t k = 0; k < line.x.size(); ++k)
      if (std::isfinite(line.y[k]) && (line.points_only || CarriesSymbol(k, line.x.size(), l)))
        svg += Symbol(l, X(line.x[k]), Y(std::clamp(line.y[k], panel.y_min, panel.y_max)), line.color);
  }
  return svg + labels;
}

// The legend's entries below the panels, the first `top` of the page above them.
std::string LegendSvg(const std::vector<PlotPanel>& panels, const std::vector<LegendItem>& items,
                      const std::vector<LegendEntry>& legend, double top, double legend_row) {
  std::string svg;
  for (size_t k = 0; k < legend.size(); ++k) {
    const LegendItem& item = items[k];
    double x = legend[k].x, y = top + legend_row * (legend[k].row + 1) - 4;
    const std::string label =
        "<text x=\"" + Num(x + 30) + "\" y=\"" + Num(y) + "\">" + Escape(item.label) + "</text>\n";
    if (item.kind == LegendItem::kMarker) {  // a block, as it is drawn: upright for a marker, across for a level
      svg += "<rect x=\"" + Num(x + 7) + "\" y=\"" + Num(y - 12) +
             "\" width=\"10\" height=\"14\" fill=\"#888\" fill-opacity=\"0.35\"/>\n" + label;
      continue;
    }
    if (item.kind == LegendItem::kLevel) {
      svg += "<rect x=\"" + Num(x) + "\" y=\"" + Num(y - 8) +
             "\" width=\"24\" height=\"8\" fill=\"#888\" fill-opacity=\"0.35\"/>\n" + label;
      continue;
    }
    const PlotLine& line = panels.front().lines[item.line];
    if (!line.points_only)
      svg += "<line x1=\"" + Num(x) + "\" y1=\"" + Num(y - 4) + "\" x2=\"" + Num(x + 24) + "\" y2=\"" + Num(y - 4) +
             "\" stroke=\"" + line.color + "\" stroke-width=\"2\"" + (line.dashed ? " stroke-dasharray=\"6,3\"" : "") +
             "/>\n";
    svg += Symbol(item.line, x + 12, y - 4, line.color) + label;
  }
  return svg;
}

}  // namespace

std::string RenderSvg(const std::vector<PlotPanel>& panels, int columns, const std::string& title) {
  const bool alone = panels.size() == 1;
  const double w = alone ? 640 : 460, h = alone ? 380 : 330, left = 62, right = 14, top = alone ? 12 : 30, bottom = 46,
               legend_row = 20;
  const std::string heading = alone && title.empty() ? panels.front().title : title;
  int rows = static_cast<int>((panels.size() + columns - 1) / columns);
  const double page_w = w * columns;
  int legend_rows = 0;
  const std::vector<LegendItem> items = LegendItems(panels);
  const std::vector<LegendEntry> legend = LayOutLegend(items, page_w, &legend_rows);
  const double page_h = 36 + h * rows + 6 + legend_row * legend_rows;
  std::string svg = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + Num(page_w) + "\" height=\"" + Num(page_h) +
                    "\" viewBox=\"0 0 " + Num(page_w) + " " + Num(page_h) +
                    "\" font-family=\"Helvetica, Arial, sans-serif\" font-size=\"12\">\n";
  svg += "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  svg += "<text x=\"" + Num(page_w / 2) + "\" y=\"22\" text-anchor=\"middle\" font-size=\"15\">" + Escape(heading) +
         "</text>\n";
  for (size_t p = 0; p < panels.size(); ++p) {
    const PlotPanel& panel = panels[p];
    double ox = w * (p % columns), oy = 36 + h * (p / columns);
    const PlotArea area{ox, oy, ox + left, ox + w - right, oy + h - bottom, oy + top};
    svg += "<g>\n";
    if (!alone)
      svg += "<text x=\"" + Num((area.x0 + area.x1) / 2) + "\" y=\"" + Num(oy + 18) +
             "\" text-anchor=\"middle\" font-size=\"13\">" + Escape(panel.title) + "</text>\n";
    svg += AxesSvg(panel, area);
    svg += DataSvg(panel, area);
    svg += "</g>\n";
  }
  svg += LegendSvg(panels, items, legend, 36 + h * rows, legend_row);
  svg += "</svg>\n";
  return svg;
}

}  // namespace layerlab
