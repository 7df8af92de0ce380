// Line charts as standalone SVG: axes with ticks and units, a legend, and
// several panels on one page (the layout of the paper's Fig. 5).
#pragma once

#include <string>
#include <vector>

namespace layerlab {

struct PlotLine {
  std::string label;
  std::string color;  // CSS color
  bool dashed = false;
  std::vector<double> x, y;
  bool points_only = false;  // a symbol at every point, no line: a scatter
};

// A place on the x axis, e.g. the target depth: drawn as a grey band with
// its label, in the legend as a block, so that it cannot be taken for a curve.
struct PlotMarker {
  double x = 0;
  std::string label = "target depth";
};

// A value on the y axis, e.g. the target depth a peak accommodation should
// reach: a grey band across the panel with its label, in the legend as a block.
struct PlotLevel {
  double y = 0;
  std::string label = "target depth";
};

struct PlotPanel {
  std::string title;
  std::string x_label, y_label;  // with units: "accommodation (D)"
  double x_min = 0, x_max = 1, y_min = 0, y_max = 1;
  std::vector<PlotLine> lines;
  std::vector<PlotMarker> markers;
  std::vector<PlotLevel> levels;
};

// Panels laid out in `columns` columns; each panel 640 x 380 px alone, 460 x
// 330 px beside others. One title: `title` over all; each panel's own only
// when there are several (a lone panel's title is `title`, or its own when
// `title` is empty).
std::string RenderSvg(const std::vector<PlotPanel>& panels, int columns, const std::string& title);

// Text for XML and HTML: < > & " escaped.
std::string Escape(const std::string& text);

// Round-number ticks covering [lo, hi].
std::vector<double> NiceTicks(double lo, double hi, int target_count);

}  // namespace layerlab
