// layerlab eyebox SCENE.json --patterns DIR --target-scene T.json --accommodation D --out DIR:
// the display seen from a grid of pupil positions and of gaze directions,
// each retinal image against the target's from the same pupil (eyebox.csv,
// eyebox.svg, index.html), and the eyebox where it stays within a PSNR drop
// of its centre.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "layerlab/analysis/eyebox_map.h"
#include "layerlab/analysis/report_parts.h"
#include "layerlab/analysis/svg_plot.h"
#include "layerlab/app/command_line.h"
#include "layerlab/app/command_result.h"
#include "layerlab/app/commands.h"
#include "layerlab/app/natural_viewing.h"
#include "layerlab/app/number_list.h"
#include "layerlab/app/target_option.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/progress.h"
#include "layerlab/framework/staged_output.h"
#include "layerlab/solvers/solution_writer.h"
#include "layerlab/solvers/solve_config.h"
#include "layerlab/systems/compile.h"

namespace layerlab::app {

namespace {

struct EyeboxCommandOptions {
  std::string scene, patterns, out, sampling, accommodation;
  TargetOption target;
  std::string range = "2", step = "1", gaze_range = "0", gaze_step = "5", gaze_field = "10,10";
  std::string field, resolution = "0.1", quality = "1";
};

// "H" or "H,V" of half ranges, each >= 0.
std::array<double, 2> HalfRanges(const std::string& text, const std::string& option, const OptionUnit& unit) {
  const std::vector<double> v = ParseNumberList(text, option, unit);
  if (v.size() > 2) throw Error(option + ": give one half range, or two (x,y)");
  return {v[0], v.size() == 2 ? v[1] : v[0]};
}

std::string Extent(double value, bool at_least, double unit, const char* name) {
  return (at_least ? ">= " : "") + FormatFixed(value * unit, 2) + " " + name;
}

ReportSection EyeboxSection(const EyeboxMap& map) {
  std::string html = "<section id=\"eyebox\"><h2>Eyebox</h2>\n<p>Retinal PSNR within " +
                     FormatFixed(map.quality_db, 2) + " dB of the centre's (" +
                     FormatFixed(map.pupil.centre().psnr_db, 2) + " dB): ";
  const auto pupil = map.pupil.within(map.quality_db);
  const auto pupil_edge = map.pupil.within_reaches_edge(map.quality_db);
  html += Extent(pupil[0], pupil_edge[0], 1e3, "mm") + " x " + Extent(pupil[1], pupil_edge[1], 1e3, "mm");
  if (!map.gaze.poses.empty()) {
    const auto gaze = map.gaze.within(map.quality_db);
    const auto gaze_edge = map.gaze.within_reaches_edge(map.quality_db);
    html += "; over the gaze " + Extent(gaze[0], gaze_edge[0], kDegreesPerRadian, "deg") + " x " +
            Extent(gaze[1], gaze_edge[1], kDegreesPerRadian, "deg");
  }
  html += ".</p>\n" +
          HtmlFigure(Picture("PSNR and brightness over the eyebox", "eyebox.svg", {{"CSV", "eyebox.csv"}})) +
          "</section>\n";
  return {"eyebox", "Eyebox", {"eyebox.svg", "eyebox.csv"}, html};
}

ReportSection SwimSection(const std::vector<LayerSwim>& swim) {
  std::string html =
      "<section id=\"swim\"><h2>Pupil swim</h2>\n<p>How a still point of each layer seems to move as the pupil "
      "moves, beyond the parallax of a point at the layer's depth (0 through ideal optics).</p>\n"
      "<table><tr><th>layer</th><th>largest swim (arcmin)</th><th>largest rate (arcmin/mm)</th></tr>\n";
  for (const LayerSwim& l : swim)
    html += "<tr><td>" + Escape(l.layer) + "</td><td>" + HtmlNumber(l.max_arcmin, 2) + "</td><td>" +
            HtmlNumber(l.rate_arcmin_per_mm, 2) + "</td></tr>\n";
  html += "</table>\n" + HtmlFigure(Picture("Swim along x against the pupil's x", "swim.svg", {{"CSV", "swim.csv"}})) +
          "</section>\n";
  return {"swim", "Pupil swim", {"swim.svg", "swim.csv"}, html};
}

// The map's options from the command line's, each checked with its option's name.
EyeboxMapOptions ReadEyeboxOptions(const EyeboxCommandOptions& o) {
  EyeboxMapOptions options;
  options.accommodation_diopters = ParseOptionValue(o.accommodation, "--accommodation", kDiopters, true);
  options.pupil_half_range_m = HalfRanges(o.range, "--eyebox-range", kMillimeters);
  for (double& v : options.pupil_half_range_m) v *= 1e-3;
  options.pupil_step_m = ParseOptionValue(o.step, "--eyebox-step", kMillimeters) * 1e-3;
  options.gaze_half_range_rad = HalfRanges(o.gaze_range, "--gaze-range", kDegrees);
  for (double& v : options.gaze_half_range_rad) v *= kRadiansPerDegree;
  options.gaze_step_rad = ParseOptionValue(o.gaze_step, "--gaze-step", kDegrees) * kRadiansPerDegree;
  options.gaze_field_deg = HalfRanges(o.gaze_field, "--gaze-field", kDegrees);
  if (!o.field.empty()) options.field_deg = HalfRanges(o.field, "--field", kDegrees);
  options.resolution_deg = ParseOptionValue(o.resolution, "--resolution", kDegrees);
  options.quality_db = ParseOptionValue(o.quality, "--quality", {Dimension::kFraction, ""});
  CheckRetinaSampling(options.gaze_field_deg[0], options.gaze_field_deg[1], options.resolution_deg, "--gaze-field",
                      "--resolution");
  if (!o.field.empty())
    CheckRetinaSampling(options.field_deg[0], options.field_deg[1], options.resolution_deg, "--field", "--resolution");
  return options;
}

void RunEyeboxCommand(const EyeboxCommandOptions& o) {
  Scene scene = LoadScene(o.scene);
  DisplaySystem system = Compile(scene);
  SolveConfig config = ReadSolveConfig(scene, system);
  if (!o.sampling.empty()) config.sampling = SamplingFromString(o.sampling);
  SolveConfig given;
  ApplyTargetOption(o.target, given);
  given.target_moved_m = config.target_moved_m;  // a binocular eye's own display: the target seen from its axis
  if (!o.target.given()) throw Error("eyebox: give the target: --target LF_DIR or --target-scene T.json");
  const EyeboxMapOptions options = ReadEyeboxOptions(o);

  StagedOutput stage(o.out, "eyebox", {"eyebox.csv", "eyebox.svg", "swim.csv", "swim.svg", "index.html"},
                     {{o.scene, "the scene"},
                      {o.patterns, "the patterns"},
                      {given.target, "the target"},
                      {given.target_scene, "the target scene"}});
  const NaturalViewing natural(given, config.sampling);
  const LightField* target_lf = natural.light_field();
  const LightFieldGeometry g = target_lf ? target_lf->geometry : DisplayLightFieldGeometry(system);
  DisplayModel model(system, g, config.sampling);
  const Patterns t = ReadPatterns(model, o.patterns);
  const auto start = std::chrono::steady_clock::now();
  std::unique_ptr<Progress> progress;
  try {
    const EyeboxMap map = MapEyebox(model, t, natural.radiance(), options, [&](size_t done, size_t total) {
      if (!progress) progress = std::make_unique<Progress>("eyebox", total);
      progress->Update(done, "poses");
    });
    if (progress) progress->Finish(std::to_string(map.pupil.poses.size() + map.gaze.poses.size()) + " poses");
    WriteEyeboxMap(map, stage.staging());
    // Pupil swim behind real optics (an ideal layer's is 0): over the pupil grid's x range.
    const bool real = std::any_of(system.layers.begin(), system.layers.end(),
                                  [](const VirtualLayer& l) { return l.ray_map != nullptr; });
    std::vector<LayerSwim> swim;
    if (real && options.pupil_half_range_m[0] > 0) {
      const int steps = std::max(2, int(std::lround(options.pupil_half_range_m[0] / options.pupil_step_m)));
      swim = MeasurePupilSwim(system, options.pupil_half_range_m[0], steps);
      WritePupilSwim(swim, stage.staging());
    }
    RunReportPage page =
        CommandPage("eyebox", o.scene, scene.name.empty() ? std::filesystem::path(o.scene).stem().string() : scene.name,
                    scene.description, CommandLine());
    page.system = &system;
    page.steps = {{"eyebox (" + std::to_string(map.pupil.poses.size() + map.gaze.poses.size()) + " poses)",
                   std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()}};
    page.warnings = system.warnings;
    page.sections.push_back(EyeboxSection(map));
    if (!swim.empty()) page.sections.push_back(SwimSection(swim));
    WriteReportPage(page, stage.staging());
    stage.Commit();
    const auto pupil = map.pupil.within(map.quality_db);
    CommandResult result("eyebox");
    result["pupil_swim"] = nlohmann::json::array();
    for (const LayerSwim& l : swim) {
      char line[256];
      std::snprintf(line, sizeof line,
                    "pupil swim of layer %s: up to %.2f arcmin, %.2f arcmin per mm of pupil motion\n", l.layer.c_str(),
                    l.max_arcmin, l.rate_arcmin_per_mm);
      result.Text(line);
      result["pupil_swim"].push_back(
          {{"layer", l.layer}, {"max_arcmin", l.max_arcmin}, {"arcmin_per_mm", l.rate_arcmin_per_mm}});
    }
    const auto edge = map.pupil.within_reaches_edge(map.quality_db);
    const std::string x = Extent(pupil[0], edge[0], 1e3, "mm"), y = Extent(pupil[1], edge[1], 1e3, "mm");
    char line[512];
    std::snprintf(line, sizeof line,
                  "wrote %s/{index.html,eyebox.csv,eyebox.svg}: centre %.2f dB; within %.2f dB: %s x %s\n",
                  o.out.c_str(), map.pupil.centre().psnr_db, map.quality_db, x.c_str(), y.c_str());
    result.Text(line);
    result["out"] = o.out;
    result["centre_psnr_db"] = map.pupil.centre().psnr_db;
    result["quality_db"] = map.quality_db;
    result["pupil_extent_within_quality_m"] = {pupil[0], pupil[1]};  // "at least" where it reaches the grid's edge
    result["pupil_extent_reaches_edge"] = {edge[0], edge[1]};
    result.Print();
  } catch (const Error& e) {
    throw stage.Explain(e);
  }
}

}  // namespace

void AddEyeboxCommand(CLI::App& app) {
  auto o = std::make_shared<EyeboxCommandOptions>();
  CLI::App* cmd = app.add_subcommand(
      "eyebox", "The display seen across the eyebox and over the gaze: retinal PSNR, brightness, vignetting");
  cmd->add_option("scene", o->scene, "Display scene file (JSON)")->required();
  cmd->add_option("--patterns", o->patterns, "Output folder of `layerlab solve` (its patterns/)")->required();
  AddTargetOptions(cmd, o->target, ": what each pupil should see (a scene's traced from any pupil)");
  cmd->add_option("--accommodation", o->accommodation, "The eye's focus: D, or with units (\"1.0 D\", \"0.5 m\")")
      ->required();
  cmd->add_option("--eyebox-range", o->range, "Pupil offsets -R..R: mm, or X,Y half ranges (default 2)");
  cmd->add_option("--eyebox-step", o->step, "Pupil grid step: mm (default 1)");
  cmd->add_option("--gaze-range", o->gaze_range, "Gaze -G..G: degrees, or X,Y half ranges (default 0: no gaze grid)");
  cmd->add_option("--gaze-step", o->gaze_step, "Gaze grid step: degrees (default 5)");
  cmd->add_option("--gaze-field", o->gaze_field, "Retinal field W,H around each gaze: degrees (default 10,10)");
  cmd->add_option("--field", o->field, "Retinal field W,H of the pupil grid: degrees (default: the display's)");
  cmd->add_option("--resolution", o->resolution, "Retinal sample size: degrees or \"3 arcmin\" (default 0.1)");
  cmd->add_option("--quality", o->quality,
                  "The eyebox: where the PSNR stays within this many dB of the centre's "
                  "(default 1)");
  cmd->add_option("--sampling", o->sampling, "Layer sampling: nearest or bilinear (default: the scene's)");
  cmd->add_option("--out", o->out, "Output folder")->required();
  cmd->callback([o] { RunEyeboxCommand(*o); });
}

}  // namespace layerlab::app
