// analysis/svg_plot.h: one title per plot, a marker that cannot be taken for a curve, and lines that
// coincide told apart by their symbols.
#include <gtest/gtest.h>

#include "layerlab/analysis/svg_plot.h"

namespace layerlab {
namespace {

size_t Count(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

PlotPanel Panel(const std::string& title) {
  PlotPanel p;
  p.title = title;
  p.lines = {{"a", "#d62728", false, {0, 1}, {0, 1}}, {"b", "#1f77b4", false, {0, 1}, {1, 0}}};
  return p;
}

TEST(SvgPlot, ALonePanelHasOneTitle) {
  const std::string svg = RenderSvg({Panel("PSNR against wall time")}, 1, "");
  EXPECT_EQ(Count(svg, "PSNR against wall time"), 1u) << svg;
  const std::string titled = RenderSvg({Panel("panel title")}, 1, "Plot title");
  EXPECT_EQ(Count(titled, "Plot title"), 1u);
  EXPECT_EQ(Count(titled, "panel title"), 0u);
  // Several panels: the plot's title once, and each panel's own.
  const std::string two = RenderSvg({Panel("left"), Panel("right")}, 2, "Both");
  EXPECT_EQ(Count(two, ">Both<"), 1u);
  EXPECT_EQ(Count(two, ">left<"), 1u);
  EXPECT_EQ(Count(two, ">right<"), 1u);
}

TEST(SvgPlot, AMarkerIsABandWithItsLabelNotALine) {
  PlotPanel p = Panel("contrast");
  p.markers.push_back({0.5, "target depth"});
  const std::string svg = RenderSvg({p}, 1, "");
  EXPECT_EQ(Count(svg, "<polyline"), 2u) << "only the two curves are lines";
  EXPECT_EQ(Count(svg, "fill=\"#888\""), 2u) << "the band, and its block in the legend";
  EXPECT_EQ(Count(svg, ">target depth<"), 3u) << "labelled on the plot (text and tooltip) and in the legend";
  EXPECT_EQ(Count(svg, "stroke-dasharray"), 0u) << "no dashed line that could pass for a curve";
}

// Issue 50: a sweep's peak accommodation is drawn against the target's depth, a grey band across the
// panel at that value, labelled there and in the legend, not a line that could pass for a curve.
TEST(SvgPlot, ALevelIsABandAcrossThePanelAtItsValue) {
  PlotPanel p = Panel("peak accommodation");
  p.y_min = 0, p.y_max = 2;
  p.levels.push_back({1.5, "target depth 1.5 D"});
  const std::string svg = RenderSvg({p}, 1, "");
  EXPECT_EQ(Count(svg, "<polyline"), 2u) << "only the two curves are lines";
  EXPECT_EQ(Count(svg, ">target depth 1.5 D<"), 3u) << "labelled on the plot (text and tooltip) and in the legend";
  // The band spans the plot area (x 62 to 626 of a lone 640 px panel) and is centred at y = 1.5: the
  // plot area runs from y 370 (0) to 48 (2), so 1.5 lies at 370 - 0.75 * 322 = 128.5.
  EXPECT_NE(svg.find("<rect x=\"62.00\" y=\"124.50\" width=\"564.00\" height=\"8\" fill=\"#888\""), std::string::npos)
      << svg;
}

// Two runs with the same curve (issue 50: four runs showed as three lines): each line's points carry
// its own symbol, hollow, so both show where they overlap; the legend shows the symbols too.
TEST(SvgPlot, CoincidingLinesKeepTheirSymbols) {
  PlotPanel p;
  p.lines = {{"a", "#d62728", false, {0, 1, 2, 3}, {10, 20, 25, 27}},
             {"b", "#1f77b4", false, {0, 1, 2, 3}, {10, 20, 25, 27}}};
  const std::string svg = RenderSvg({p}, 1, "");
  EXPECT_EQ(Count(svg, "<circle"), 4u + 1u) << "line a's four points and its legend entry";
  EXPECT_EQ(Count(svg, "width=\"6\" height=\"6\""), 4u + 1u) << "line b's four points and its legend entry";
  EXPECT_EQ(Count(svg, "fill=\"white\" stroke=\"#1f77b4\""), 5u);
  // A long line carries about 16 symbols, each line at its own phase.
  PlotPanel many;
  std::vector<double> x(300), y(300);
  for (size_t k = 0; k < x.size(); ++k) x[k] = double(k), y[k] = double(k % 7);
  many.x_max = 300, many.y_max = 7;
  many.lines = {{"a", "#d62728", false, x, y}, {"b", "#1f77b4", false, x, y}};
  const std::string long_svg = RenderSvg({many}, 1, "");
  EXPECT_GE(Count(long_svg, "<circle"), 14u);
  EXPECT_LE(Count(long_svg, "<circle"), 20u);
  EXPECT_EQ(Count(long_svg, "<circle"), Count(long_svg, "width=\"6\" height=\"6\"")) << "as many symbols on each line";
}

}  // namespace
}  // namespace layerlab
