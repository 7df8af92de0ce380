#include "layerlab/analysis/contrast_eyebox.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <tuple>

#include "layerlab/analysis/svg_plot.h"

namespace layerlab {
namespace {

// A display's own curve (not natural viewing, not factorized for another display).
bool IsDisplayCurve(const ContrastCurve& c) { return !c.scene.empty() && c.factorized_for.empty(); }

double PeakError(const ContrastCurve& c) { return c.estimate.at - c.target_diopters; }

}  // namespace

std::string ContrastEyeboxCsv(const std::vector<ContrastCurve>& curves) {
  std::string csv = "display,target_D,frequency_cpd,pupil_x_mm,pupil_y_mm,peak_D,placed,peak_error_D\n";
  char line[160];
  for (const ContrastCurve& c : curves) {
    if (!IsDisplayCurve(c)) continue;
    std::snprintf(line, sizeof line, ",%.4f,%.4f,%.4f,%.4f,%.4f,%s,%.4f\n", c.target_diopters, c.frequency,
                  c.pupil_moved_m[0] * 1e3, c.pupil_moved_m[1] * 1e3, c.estimate.at, c.estimate.flat ? "no" : "yes",
                  PeakError(c));
    csv += c.scene + line;
  }
  return csv;
}

std::string ContrastEyeboxSvg(const std::vector<ContrastCurve>& curves) {
  static const char* kColors[] = {"#d62728", "#1f77b4", "#ff7f0e", "#9467bd", "#2ca02c", "#8c564b", "#e377c2"};
  // (target, frequency) -> display -> the peak errors along x and along y, by pupil position (mm).
  using Line = std::map<double, double>;
  std::map<std::pair<double, double>, std::map<std::string, std::pair<Line, Line>>> panels;
  std::vector<std::string> displays;
  double lo = 0, hi = 0, range_mm = 0;
  for (const ContrastCurve& c : curves) {
    if (!IsDisplayCurve(c) || c.estimate.flat) continue;
    const double x = c.pupil_moved_m[0] * 1e3, y = c.pupil_moved_m[1] * 1e3, e = PeakError(c);
    std::pair<Line, Line>& lines = panels[{c.target_diopters, c.frequency}][c.scene];
    if (y == 0) lines.first[x] = e;
    if (x == 0) lines.second[y] = e;
    if (std::find(displays.begin(), displays.end(), c.scene) == displays.end()) displays.push_back(c.scene);
    lo = std::min(lo, e), hi = std::max(hi, e);
    range_mm = std::max({range_mm, std::abs(x), std::abs(y)});
  }
  std::vector<PlotPanel> plots;
  for (const auto& [target, of_display] : panels) {
    PlotPanel panel;
    char title[96];
    std::snprintf(title, sizeof title, "target %.2f D, %.1f cpd", target.first, target.second);
    panel.title = title;
    panel.x_label = "pupil position (mm)";
    panel.y_label = "peak error (D)";
    panel.x_min = -range_mm, panel.x_max = range_mm;
    const double pad = std::max(0.05, 0.1 * (hi - lo));
    panel.y_min = lo - pad, panel.y_max = hi + pad;
    for (const auto& [display, lines] : of_display) {
      const size_t index = size_t(std::find(displays.begin(), displays.end(), display) - displays.begin());
      for (int axis = 0; axis < 2; ++axis) {
        const Line& points = axis == 0 ? lines.first : lines.second;
        PlotLine line{
            display + (axis == 0 ? ", pupil along x" : ", pupil along y"), kColors[index % 7], axis == 1, {}, {}};
        for (const auto& [at, error] : points) line.x.push_back(at), line.y.push_back(error);
        panel.lines.push_back(std::move(line));
      }
    }
    plots.push_back(std::move(panel));
  }
  return RenderSvg(plots, std::min<int>(int(plots.size()), 2),
                   "Accommodation response across the eyebox: the contrast peak's error");
}

}  // namespace layerlab
