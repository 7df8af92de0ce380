#include "layerlab/analysis/layout_svg.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "layerlab/analysis/svg_plot.h"
#include "layerlab/systems/intermediate_images.h"

namespace layerlab {
namespace {

constexpr double kWidth = 1000, kLeft = 70, kRight = 40, kRowHeight = 96, kTop = 46;
const char* kBranchColors[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b"};

std::string Num(double v) { return FormatFixed(v, 1); }
std::string Label(double v, int decimals) { return FormatFixed(v == 0 ? 0.0 : v, decimals); }  // no "-0"

std::string Text(double x, double y, const std::string& text, const std::string& extra = "") {
  return "<text x=\"" + Num(x) + "\" y=\"" + Num(y) + "\" " + extra + ">" + Escape(text) + "</text>\n";
}

std::string Line(double x1, double y1, double x2, double y2, const std::string& style) {
  return "<line x1=\"" + Num(x1) + "\" y1=\"" + Num(y1) + "\" x2=\"" + Num(x2) + "\" y2=\"" + Num(y2) + "\" " + style +
         "/>\n";
}

// Positions of one branch's elements; a flat element without a place of its own
// is drawn halfway between its placed neighbours.
std::vector<double> DrawnPositions(const VirtualLayer& back) {
  std::vector<double> out;
  double last = 0;
  for (size_t i = 0; i < back.path.size(); ++i) {
    if (back.path[i].position_m) {
      out.push_back(last = *back.path[i].position_m);
      continue;
    }
    double next = back.position_m;
    for (size_t j = i + 1; j < back.path.size(); ++j)
      if (back.path[j].position_m) {
        next = *back.path[j].position_m;
        break;
      }
    out.push_back(0.5 * (last + next));
  }
  return out;
}

std::string Glyph(const PathStep& step, double x, double y) {
  const std::string name = Text(x, y - 34, step.element, "text-anchor=\"middle\" font-size=\"11\"");
  switch (step.kind) {
    case ElementKind::kLens: {
      const bool converging = step.power_diopters > 0;
      const double tip = converging ? -6 : 6;
      return name + Line(x, y - 26, x, y + 26, "stroke=\"#333\" stroke-width=\"2\"") + "<path d=\"M" + Num(x - 5) +
             " " + Num(y - 26 - tip) + " L" + Num(x) + " " + Num(y - 26) + " L" + Num(x + 5) + " " + Num(y - 26 - tip) +
             " M" + Num(x - 5) + " " + Num(y + 26 + tip) + " L" + Num(x) + " " + Num(y + 26) + " L" + Num(x + 5) + " " +
             Num(y + 26 + tip) + "\" fill=\"none\" stroke=\"#333\" stroke-width=\"2\"/>\n";
    }
    case ElementKind::kMirror:
      if (step.power_diopters != 0)
        return name + "<path d=\"M" + Num(x - 8) + " " + Num(y - 24) + " Q" +
               Num(x + (step.power_diopters > 0 ? 10 : -10)) + " " + Num(y) + " " + Num(x - 8) + " " + Num(y + 24) +
               "\" fill=\"none\" stroke=\"#555\" stroke-width=\"3\"/>\n";
      return name + Line(x - 14, y + 20, x + 14, y - 20, "stroke=\"#555\" stroke-width=\"3\"");
    case ElementKind::kCombiner:
      return name +
             Line(x - 14, y + 20, x + 14, y - 20, "stroke=\"#69c\" stroke-width=\"3\" stroke-dasharray=\"5,3\"") +
             Text(x, y + 40, step.port, "text-anchor=\"middle\" font-size=\"10\" fill=\"#555\"");
    case ElementKind::kInlineOptic:
      return name + "<rect x=\"" + Num(x - 3) + "\" y=\"" + Num(y - 18) +
             "\" width=\"6\" height=\"36\" fill=\"#cde\" "
             "stroke=\"#357\"/>\n";
    default:
      return name;
  }
}

// Where path lengths (m, the physical rows) and diopters (the eye-space strip) lie on the page.
struct LayoutScale {
  double farthest = 0, max_diopters = 0;
  double plot_width = kWidth - kLeft - kRight;
  double x_of(double position) const { return kLeft + plot_width * position / (farthest * 1.06); }
  double x_of_diopters(double D) const { return kLeft + plot_width * (1 - D / max_diopters); }
};

// A branch's physical row: the eye, the optics and the panels, with their real intermediate images;
// where each of its panels is drawn on the page's x axis into panel_x.
std::string BranchRowSvg(const DisplaySystem& s, size_t b, const LayoutScale& scale, std::vector<double>* panel_x) {
  auto x_of = [&](double position) { return scale.x_of(position); };
  const Branch& branch = s.branches[b];
  const std::string color = kBranchColors[b % 6];
  const double y = kTop + b * kRowHeight + kRowHeight / 2;
  const VirtualLayer& back = s.layers[branch.layers.back()];
  std::string svg = Text(4, y - 40, branch.name, "font-size=\"11\" fill=\"" + color + "\"");
  svg += Line(x_of(0), y, x_of(back.position_m), y, "stroke=\"" + color + "\" stroke-width=\"1\"");
  svg += "<ellipse cx=\"" + Num(x_of(0) - 10) + "\" cy=\"" + Num(y) +
         "\" rx=\"10\" ry=\"14\" fill=\"#fff\" stroke=\"#333\"/>\n";
  svg += Text(x_of(0) - 10, y + 30, "eye", "text-anchor=\"middle\" font-size=\"11\"");
  const std::vector<double> at = DrawnPositions(back);
  for (size_t i = 0; i < back.path.size(); ++i)
    if (back.path[i].kind != ElementKind::kPanel) svg += Glyph(back.path[i], x_of(at[i]), y);
  for (int k : branch.layers) {
    const VirtualLayer& l = s.layers[k];
    const double x = x_of(l.position_m);
    (*panel_x)[k] = x;
    svg += "<rect x=\"" + Num(x - 2.5) + "\" y=\"" + Num(y - 22) + "\" width=\"5\" height=\"44\" fill=\"" + color +
           "\"/>\n";
    svg += Text(x + 4, y + 34 + 10 * l.position_in_branch, l.name, "font-size=\"11\" fill=\"" + color + "\"");
    // Real intermediate images (a relay's): where the light converges on its way to the eye.
    for (const IntermediateImage& image : IntermediateImages(l)) {
      if (!image.real || !(image.position_m > 0) || image.position_m > l.position_m) continue;
      const double xi = x_of(image.position_m);
      svg += Line(xi, y - 14, xi, y + 14, "stroke=\"" + color + "\" stroke-width=\"1.5\" stroke-dasharray=\"2,2\"");
      svg += Text(xi, y - 18 - 10 * l.position_in_branch, "real image of " + l.name,
                  "text-anchor=\"middle\" font-size=\"9\" fill=\"" + color + "\"");
    }
  }
  return svg;
}

// The eye-space strip, below the physical rows' path-length axis: a band of connectors, one from each
// panel's place on that axis (a dot of its branch's color) down to its image's mark on a diopter axis
// (near on the left, infinity on the right). Nothing else is drawn in the band, so that no connector
// crosses a label. Each mark's label hangs below the axis on a leader, to its right, on the lowest
// level where it clears the labels and leaders already placed; a tick label a leader would cross is
// left out (the mark's label gives its value).
constexpr double kConnectorBand = 56, kMarkHeight = 40, kLevel = 13, kFontSize = 10;

std::string ImageLabel(const VirtualLayer& l) {
  return l.name + " " + FormatFixed(l.diopters, 2) + " D" + (l.inverted ? " (inverted)" : "");
}

// Each layer's label level (0 nearest the axis), placed from the right: a label spans from its mark
// rightwards, so it must clear the labels on its level and pass below every leader in its span.
std::vector<int> LabelLevels(const DisplaySystem& s, const LayoutScale& scale) {
  const size_t n = s.layers.size();
  std::vector<double> x(n), right(n);
  for (size_t k = 0; k < n; ++k) {
    x[k] = scale.x_of_diopters(s.layers[k].diopters);
    right[k] = x[k] + 4 + 0.62 * kFontSize * static_cast<double>(ImageLabel(s.layers[k]).size());
  }
  std::vector<size_t> order(n);
  for (size_t k = 0; k < n; ++k) order[k] = k;
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return x[a] > x[b]; });
  std::vector<int> level(n, -1);
  for (size_t i = 0; i < n; ++i) {
    const size_t k = order[i];
    for (int L = 0;; ++L) {
      bool clear = true;
      for (size_t j = 0; j < i && clear; ++j) {
        const size_t m = order[j];  // placed, at or right of k
        const bool label_overlaps = level[m] == L && x[m] < right[k] + 6 && x[k] < right[m] + 6;
        const bool leader_crosses = x[m] <= right[k] + 2 && level[m] >= L;
        clear = !label_overlaps && !leader_crosses;
      }
      if (clear) {
        level[k] = L;
        break;
      }
    }
  }
  return level;
}

struct StripSvg {
  std::string svg;
  double bottom = 0;
};

StripSvg EyeSpaceStripSvg(const DisplaySystem& s, const LayoutScale& scale, double strip_top,
                          const std::vector<double>& panel_x) {
  auto x_of_diopters = [&](double D) { return scale.x_of_diopters(D); };
  const double marks_top = strip_top + kConnectorBand, axis_y = marks_top + kMarkHeight;
  const double near_x = x_of_diopters(s.eye.accommodation_max_diopters);
  std::string svg = "<rect x=\"" + Num(near_x) + "\" y=\"" + Num(marks_top - 6) + "\" width=\"" +
                    Num(x_of_diopters(s.eye.accommodation_min_diopters) - near_x) + "\" height=\"" +
                    Num(axis_y - marks_top + 6) + "\" fill=\"#eee\"/>\n";
  svg += Line(kLeft, axis_y, kLeft + scale.plot_width, axis_y, "stroke=\"#333\"");
  const std::vector<int> level = LabelLevels(s, scale);
  int levels = 0;
  for (int L : level) levels = std::max(levels, L + 1);
  auto baseline = [&](int L) { return axis_y + 34 + kLevel * L; };
  for (double D : NiceTicks(0, scale.max_diopters, 8)) {
    if (D > scale.max_diopters) continue;
    const double x = x_of_diopters(D);
    const std::string text = Label(D, 1) + " D";
    const double half = 0.31 * kFontSize * static_cast<double>(text.size()) + 2;
    bool crossed = false;
    for (const VirtualLayer& l : s.layers) crossed |= std::fabs(x_of_diopters(l.diopters) - x) < half;
    svg += Line(x, axis_y, x, axis_y + 5, "stroke=\"#333\"");
    if (!crossed) svg += Text(x, axis_y + 17, text, "text-anchor=\"middle\" font-size=\"10\"");
  }
  for (size_t k = 0; k < s.layers.size(); ++k) {
    const VirtualLayer& l = s.layers[k];
    const std::string color = kBranchColors[l.branch % 6];
    const double x = x_of_diopters(l.diopters), y = baseline(level[k]);
    svg += "<circle cx=\"" + Num(panel_x[k]) + "\" cy=\"" + Num(strip_top) + "\" r=\"2.5\" fill=\"" + color + "\"/>\n";
    svg += Line(panel_x[k], strip_top, x, marks_top,
                "stroke=\"" + color + "\" stroke-dasharray=\"3,3\" stroke-opacity=\"0.7\" class=\"connector\"");
    svg += Line(x, marks_top, x, axis_y, "stroke=\"" + color + "\" stroke-width=\"3\"");
    svg += Line(x, axis_y, x, y - 3, "stroke=\"" + color + "\" stroke-width=\"1\" class=\"leader\"");
    svg += Text(x + 4, y, ImageLabel(l), "font-size=\"10\" fill=\"" + color + "\"");
  }
  const double caption = baseline(levels) + 8;
  svg += Text(kLeft, caption,
              "Images of the panels in eye space (diopters from the eye; 0 D is infinity; grey: the accommodation "
              "range), each joined to its panel's place above",
              "font-size=\"13\" font-weight=\"bold\"");
  return {svg, caption + 12};
}

}  // namespace

std::string RenderLayoutSvg(const DisplaySystem& s, bool standalone) {
  const size_t rows = s.branches.size();
  LayoutScale scale;
  for (const VirtualLayer& l : s.layers) {
    scale.farthest = std::max(scale.farthest, l.position_m);
    scale.max_diopters = std::max(scale.max_diopters, l.diopters);
  }
  scale.max_diopters = std::max({scale.max_diopters * 1.1, s.eye.accommodation_max_diopters, 0.5});
  const double strip_top = kTop + rows * kRowHeight + 24;  // below the path-length axis and its labels
  std::vector<double> panel_x(s.layers.size());
  std::string rows_svg;
  for (size_t b = 0; b < rows; ++b) rows_svg += BranchRowSvg(s, b, scale, &panel_x);
  const StripSvg strip = EyeSpaceStripSvg(s, scale, strip_top, panel_x);
  const double height = strip.bottom;

  std::string svg = std::string("<svg ") + (standalone ? "xmlns=\"http://www.w3.org/2000/svg\" " : "") + "width=\"" +
                    Num(kWidth) + "\" height=\"" + Num(height) + "\" viewBox=\"0 0 " + Num(kWidth) + " " + Num(height) +
                    "\" font-family=\"Liberation Sans, Arial, "
                    "sans-serif\" role=\"img\" aria-label=\"optical layout\">\n";
  svg += "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  svg += Text(kLeft, 20, "Optical path unfolded from the eye, to scale (path length from the pupil, mm)",
              "font-size=\"14\" font-weight=\"bold\"");

  // The physical rows: one per branch.
  svg += rows_svg;
  for (double mm : NiceTicks(0, scale.farthest * 1.06e3, 8)) {
    const double x = scale.x_of(mm * 1e-3), y = kTop + rows * kRowHeight;
    svg += Line(x, y - 4, x, y + 2, "stroke=\"#999\"") +
           Text(x, y + 14, Label(mm, 0), "text-anchor=\"middle\" font-size=\"10\" fill=\"#555\"");
  }
  svg += strip.svg;
  return svg + "</svg>\n";
}

}  // namespace layerlab
