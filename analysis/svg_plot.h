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
};

struct PlotMarker {  // a vertical line, e.g. the target depth
  double x = 0;
  std::string color = "#2a2";
  bool dashed = true;
};

struct PlotPanel {
  std::string title;
  std::string x_label, y_label;  // with units: "accommodation (D)"
  double x_min = 0, x_max = 1, y_min = 0, y_max = 1;
  std::vector<PlotLine> lines;
  std::vector<PlotMarker> markers;
};

// Panels laid out in `columns` columns; each panel about 360 x 260 px.
std::string RenderSvg(const std::vector<PlotPanel>& panels, int columns, const std::string& title);

// Text for XML and HTML: < > & " escaped.
std::string Escape(const std::string& text);

// Round-number ticks covering [lo, hi].
std::vector<double> NiceTicks(double lo, double hi, int target_count);

}  // namespace layerlab
