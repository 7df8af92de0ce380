// The run's moving target (run.frames): the target scene solved frame by
// frame, each frame from the one before (analysis/frame_sequence.h), into
// OUT/frames: frames.csv, frames.txt and a plot of each frame's PSNR (beside
// its cold solve's) and seconds.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <tuple>

#include "layerlab/analysis/frame_sequence.h"
#include "layerlab/analysis/run_steps.h"
#include "layerlab/analysis/svg_plot.h"
#include "layerlab/framework/atomic_file.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/progress.h"

namespace layerlab {
namespace {

// [lo, hi] of the finite values of every line, widened by a margin (and to a span of at least `least`).
std::pair<double, double> Range(const std::vector<PlotLine>& lines, double least) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const PlotLine& line : lines)
    for (double v : line.y)
      if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
  if (!std::isfinite(lo)) return {0, 1};
  const double pad = std::max(0.08 * (hi - lo), least / 2);
  return {lo - pad, hi + pad};
}

PlotLine Line(const std::string& label, const std::string& color, bool dashed = false, bool points_only = false) {
  PlotLine line;
  line.label = label, line.color = color, line.dashed = dashed, line.points_only = points_only;
  return line;
}

PlotPanel Panel(const std::string& title, const std::string& y_label, double frames) {
  PlotPanel panel;
  panel.title = title, panel.x_label = "frame", panel.y_label = y_label;
  panel.x_min = 0, panel.x_max = std::max(1.0, frames - 1);
  return panel;
}

std::string FramesPlot(const FrameSequence& sequence) {
  PlotLine warm = Line("each frame, from the frame before", "#1f77b4");
  PlotLine cold = Line("the frame solved cold (reference)", "#d62728", false, true);
  PlotLine solve = Line("factorization", "#1f77b4"), render = Line("render of the target", "#7f7f7f", true);
  for (const FrameRow& r : sequence.rows) {
    warm.x.push_back(r.frame), warm.y.push_back(r.psnr_db);
    if (std::isfinite(r.cold_psnr_db)) cold.x.push_back(r.frame), cold.y.push_back(r.cold_psnr_db);
    solve.x.push_back(r.frame), solve.y.push_back(r.solve_seconds);
    render.x.push_back(r.frame), render.y.push_back(r.render_seconds);
  }
  PlotPanel psnr = Panel("light-field PSNR of each frame", "PSNR (dB)", double(sequence.rows.size()));
  psnr.lines = {warm, cold};
  std::tie(psnr.y_min, psnr.y_max) = Range(psnr.lines, 0.5);
  PlotPanel seconds = Panel("seconds of each frame", "time (s)", double(sequence.rows.size()));
  seconds.lines = {solve, render};
  seconds.y_min = 0, seconds.y_max = Range(seconds.lines, 0.1).second;
  return RenderSvg({psnr, seconds}, 2, "The moving target, frame by frame");
}

std::string FramesHtml(const std::string& summary) {
  ReportImage plot = Picture("PSNR and seconds of each frame", "frames/frames.svg",
                             {{"CSV", "frames/frames.csv"}, {"text", "frames/frames.txt"}});
  return "<section id=\"frames\"><h2>Moving target, frame by frame</h2><pre>" + Escape(summary) +
         "</pre><div class=\"grid\">" + HtmlFigure(plot, "", "plot") + "</div></section>\n";
}

std::string RunFrames(RunState& s) {
  if (!s.target->scene) throw Error("frames: internal error: the target was not rendered from its scene");
  const FrameSequenceOptions options = s.in.run.frames.sequence();
  SolveJob job;
  job.system = &s.in.system;
  job.config = s.in.solve;
  Progress progress("frames", size_t(options.frames));
  const FrameSequence sequence = SolveFrameSequence(job, *s.target->scene, options, [&](const FrameRow& r) {
    char detail[160];
    std::snprintf(detail, sizeof detail, "frames  last: %d iterations %.3f s  PSNR %.2f dB", r.iterations,
                  r.solve_seconds, r.psnr_db);
    progress.Update(size_t(r.frame + 1), detail);
  });
  progress.Finish("");
  const std::filesystem::path folder = s.out / "frames";
  std::filesystem::create_directories(folder);
  const std::string summary = FramesSummary(sequence, options, *s.target->scene);
  WriteFramesCsv(sequence, (folder / "frames.csv").string());
  WriteFileAtomically((folder / "frames.txt").string(), summary);
  WriteFileAtomically((folder / "frames.svg").string(), FramesPlot(sequence));
  s.page.sections.push_back({"frames", "Frames", {"frames/frames.svg"}, FramesHtml(summary)});
  return "frames (" + std::to_string(sequence.rows.size()) + " frames of the moving target)";
}

}  // namespace

FrameSequenceOptions FramesRunConfig::sequence() const { return {count, frame_iterations, cold_every}; }

RunSection FramesRunSection() {
  return {"frames", [](const RunInputs& in) { return in.run.frames.enabled; }, RunFrames};
}

}  // namespace layerlab
