// layerlab retina SCENE.json --patterns DIR --accommodation 0.4,1.0,1.6,2.2 --out DIR:
// what the eye sees of the display at each accommodation state, and of the
// target itself (natural viewing) when one is given, as EXR (linear,
// display-relative) and PNG (sRGB, 1 = the brightest branch's full white).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "layerlab/analysis/report_parts.h"
#include "layerlab/analysis/retina_sweep.h"
#include "layerlab/analysis/world_scene.h"
#include "layerlab/app/command_line.h"
#include "layerlab/app/command_result.h"
#include "layerlab/app/commands.h"
#include "layerlab/app/metric_flags.h"
#include "layerlab/app/natural_viewing.h"
#include "layerlab/app/number_list.h"
#include "layerlab/app/optics_options.h"
#include "layerlab/app/pose_option.h"
#include "layerlab/app/target_option.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/lightfield_io.h"
#include "layerlab/framework/progress.h"
#include "layerlab/framework/staged_output.h"
#include "layerlab/framework/warnings.h"
#include "layerlab/retina/lightfield_radiance.h"
#include "layerlab/retina/retina.h"
#include "layerlab/solvers/solution_writer.h"
#include "layerlab/solvers/solve_config.h"
#include "layerlab/systems/compile.h"
#include "layerlab/systems/eye_pose_limits.h"

namespace layerlab::app {

namespace {

struct RetinaCommandOptions {
  std::string scene, patterns, out, sampling;
  TargetOption target;
  PoseOption pose;
  OpticsOptions optics;
  std::string accommodation = "0.4,1.0,1.6,2.2", focal_stack, field, resolution = "0.05";
  std::string eyes = "scene", partner_patterns;
  std::string metrics = "psnr";
  MetricFlags metric_flags;
  std::string exr = "half";
};

// --accommodation and --focal-stack's states, sorted, without repeats.
std::vector<double> AccommodationStates(const RetinaCommandOptions& o) {
  std::vector<double> states = ParseStates(o.accommodation, "--accommodation", kDiopters, true);
  if (!o.focal_stack.empty())
    for (double d : ParseRange(o.focal_stack, "--focal-stack", kDiopters)) states.push_back(d);
  std::sort(states.begin(), states.end());
  states.erase(std::unique(states.begin(), states.end(), [](double a, double b) { return std::abs(a - b) < 1e-9; }),
               states.end());
  return states;
}

// --field in degrees, checked with the resolution; 0 x 0: the display's field of view.
std::array<double, 2> RetinaField(const RetinaCommandOptions& o, const DisplaySystem& system, double resolution) {
  double field_x = 0, field_y = 0;
  if (!o.field.empty()) {
    std::vector<double> f = ParseNumberList(o.field, "--field", kDegrees);
    if (f.size() != 2) throw Error("--field: give W,H in degrees");
    field_x = f[0], field_y = f[1];
  }
  const bool display_field = o.field.empty();
  CheckRetinaSampling(display_field ? system.fov_x_rad / kRadiansPerDegree : field_x,
                      display_field ? system.fov_y_rad / kRadiansPerDegree : field_y, resolution, "--field",
                      "--resolution");
  return {field_x, field_y};
}

void WriteRetinaPage(const RetinaCommandOptions& o, const Scene& scene, const DisplaySystem& system,
                     const DisplayModel& model, const std::vector<RetinaStateResult>& results, bool natural,
                     const std::string& folder) {
  RunReportPage page =
      CommandPage("retina", o.scene, scene.name.empty() ? std::filesystem::path(o.scene).stem().string() : scene.name,
                  scene.description, CommandLine());
  page.system = &system;
  double seconds = 0;
  for (const RetinaStateResult& r : results) seconds += r.seconds;
  page.steps = {{"retina (" + std::to_string(results.size()) + " accommodation states)", seconds}};
  AddRetinaToPage(results, ParseStates(o.accommodation, "--accommodation", kDiopters, true), natural,
                  model.white_luminance(), "", &page);
  WriteReportPage(page, folder);
}

// One eye's retinal images and page into `folder`: the display of `system` (its eye the one that looks) showing
// the patterns in `patterns`, and natural viewing of `given`'s target from the same eye. *white: the display's
// white luminance, cd/m2 (what 1 is).
std::vector<RetinaStateResult> RetinaOfEye(const RetinaCommandOptions& o, const Scene& scene,
                                           const DisplaySystem& system, const SolveConfig& config,
                                           const SolveConfig& given, const std::string& patterns,
                                           const std::string& label, const std::string& folder, double* white) {
  const std::vector<double> states = AccommodationStates(o);
  const double resolution = ParseOptionValue(o.resolution, "--resolution", kDegrees);
  const std::array<double, 2> field = RetinaField(o, system, resolution);
  const NaturalViewing seen(given, config.sampling);
  const LightField* target_lf = seen.light_field();
  const LightFieldGeometry g = target_lf ? target_lf->geometry : DisplayLightFieldGeometry(system);
  DisplayModel model(system, g, config.sampling);
  const Patterns t = ReadPatterns(model, patterns);
  const SceneRadiance& natural = seen.radiance();
  RetinaSweepOptions sweep{states,
                           resolution,
                           field[0],
                           field[1],
                           false,
                           ParseRetinalMetrics(o.metrics, "--metrics"),
                           ParseMetricSettings(o.metric_flags),
                           o.exr == "float" ? ExrPixels::kFloat : ExrPixels::kHalf,
                           WorldSceneRadiance(system)};
  Progress progress(label, states.size());
  const std::vector<RetinaStateResult> results =
      WriteRetinaSweep(model, t, natural, sweep, folder, [&](size_t done, size_t, const RetinaStateResult& r) {
        progress.Update(done, "accommodation states traced (" + r.name + ")");
      });
  progress.Finish(std::to_string(states.size()) + " states of " + FormatFixed(resolution, 3) + " deg samples");
  WriteRetinaPage(o, scene, system, model, results, bool(natural), folder);
  *white = model.white_luminance();
  return results;
}

// --eyes both: the page of the pair, each eye's images beside the other's (their own pages in left/ and right/).
void WriteBothEyesPage(const RetinaCommandOptions& o, const Scene& scene, const std::vector<DisplaySystem>& eyes,
                       const std::vector<std::vector<RetinaStateResult>>& results, double white, bool natural,
                       const std::string& folder) {
  RunReportPage page =
      CommandPage("retina", o.scene, scene.name.empty() ? std::filesystem::path(o.scene).stem().string() : scene.name,
                  scene.description, CommandLine());
  page.system = &eyes[0];
  for (size_t k = 0; k < eyes.size(); ++k) {
    const std::string side = eyes[k].eye.binocular->side < 0 ? "left" : "right";
    double seconds = 0;
    for (const RetinaStateResult& r : results[k]) seconds += r.seconds;
    page.steps.push_back({"retina, " + side + " eye (" + std::to_string(results[k].size()) + " states)", seconds});
    AddRetinaToPage(results[k], ParseStates(o.accommodation, "--accommodation", kDiopters, true), natural, white,
                    side + "/", &page);
    ReportSection& section = page.sections.back();
    section.id = side;
    section.title = side == "left" ? "Left eye" : "Right eye";
    const std::string opening = "<section id=\"retina\"><h2>";
    if (section.html.rfind(opening, 0) == 0)
      section.html = "<section id=\"" + side + "\"><h2>" + section.title + " (<a href=\"" + side +
                     "/index.html\">its page</a>): " + section.html.substr(opening.size());
  }
  WriteReportPage(page, folder);
}

// --eyes both: the scene's eye and its partner, left first, each looking as the pair's fixation turns it.
std::vector<DisplaySystem> BothEyes(const RetinaCommandOptions& o, const DisplaySystem& system) {
  if (!system.eye.binocular)
    throw Error("--eyes both: the scene's eye is not one of a binocular pair (give the eye a \"binocular\" key)");
  if (!o.target.target.empty())
    throw Error(
        "--eyes both: a light field (--target) holds the rays of one eyebox; give the target scene "
        "(--target-scene), traced from each eye");
  if (!system.eye.binocular->shared_display && o.partner_patterns.empty())
    throw Error(
        "--eyes both: each eye has a display of its own (\"display\": \"own\"): give the other eye's "
        "patterns with --partner-patterns");
  if (system.eye.binocular->shared_display && !o.partner_patterns.empty())
    throw Error("--partner-patterns: the two eyes share one display, which shows --patterns");
  DisplaySystem other = system;
  other.eye = PartnerEye(system.eye);
  if (const std::string beyond = GazeBeyondField(other, other.eye.pose); !beyond.empty())
    throw Error("--eyes both: the other eye turns to the fixation: " + beyond);
  std::vector<DisplaySystem> eyes = {system, other};
  if (system.eye.binocular->side > 0) std::swap(eyes[0], eyes[1]);
  return eyes;
}

// --metrics, --fovea and --jnd-exponent checked before anything is traced: each metric named, a target to
// score against, a retina each metric takes.
void CheckMetricOptions(const RetinaCommandOptions& o, const std::vector<DisplaySystem>& eyes,
                        const SolveConfig& given) {
  const std::vector<const RetinalMetric*> metrics = ParseRetinalMetrics(o.metrics, "--metrics");
  ParseMetricSettings(o.metric_flags);
  if (o.metric_flags.given() && !(!given.target.empty() || !given.target_scene.empty()))
    throw Error(o.metric_flags.named() +
                ": sets how the metrics score the display against natural viewing of a target: give --target or "
                "--target-scene");
  const bool natural = !given.target.empty() || !given.target_scene.empty();
  if (!natural && metrics.size() > 1)
    throw Error(
        "--metrics: the metrics score the display against natural viewing of a target: give --target or "
        "--target-scene");
  for (const DisplaySystem& eye : eyes) {
    const double resolution = ParseOptionValue(o.resolution, "--resolution", kDegrees);
    const std::array<double, 2> field = RetinaField(o, eye, resolution);
    const RetinaGrid grid =
        MakeRetinaGrid(field[0] > 0 ? field[0] * kRadiansPerDegree : eye.fov_x_rad,
                       field[1] > 0 ? field[1] * kRadiansPerDegree : eye.fov_y_rad, resolution * kRadiansPerDegree);
    if (natural) CheckMetricSize(metrics, grid.cols, grid.rows, "--metrics");
  }
}

// The result on stdout: what was written and, against natural viewing, each metric's mean over the states.
void PrintRetinaResult(const RetinaCommandOptions& o, const std::vector<DisplaySystem>& eyes,
                       const std::vector<std::vector<RetinaStateResult>>& results, double white, bool natural) {
  const bool both = eyes.size() > 1;
  const std::vector<double> states = AccommodationStates(o);
  CommandResult result("retina");
  char white_text[32];
  std::snprintf(white_text, sizeof white_text, "%.4g", white);
  result.Text("wrote " + o.out + "/{index.html," +
              (both      ? "left,right"
               : natural ? "display,natural,retina.csv"
                         : "display,retina.csv") +
              "}: " + std::to_string(states.size()) + " states" + (both ? " per eye" : "") +
              "; values are display-relative (1 = " + white_text + " cd/m2)\n");
  result["out"] = o.out;
  result["accommodation_diopters"] = states;
  result["white_cd_per_m2"] = white;
  result["eyes"] = nlohmann::json::array();
  for (size_t e = 0; e < results.size(); ++e) {
    const std::string eye = both ? (eyes[e].eye.binocular->side < 0 ? "left" : "right") : "";
    nlohmann::json mean = nlohmann::json::object();
    std::string line = eye.empty() ? "" : eye + " eye, ";
    line += "the mean over the states against natural viewing:";
    for (const MeanScore& s : MeanScoresOverStates(results[e])) {
      const RetinalMetric& m = *s.metric;
      line += (mean.empty() ? " " : ", ") + m.name + " " + FormatFixed(s.mean, m.unit == "dB" ? 2 : 4) +
              (m.unit.empty() ? "" : " " + m.unit);
      mean[m.column] = s.mean;  // retina.csv's column, its unit in the name
    }
    if (natural) result.Text(line + "\n");
    result["eyes"].push_back({{"eye", eye.empty() ? "the scene's" : eye}, {"mean_against_natural", mean}});
  }
  result.Print();
}

void RunRetinaCommand(const RetinaCommandOptions& o) {
  // Everything is read and checked before anything is written.
  Scene scene = LoadScene(o.scene);
  DisplaySystem system = Compile(scene);
  ApplyOpticsOptions(o.optics, &system);
  if (const std::string warning = ApplyPoseOption(o.pose, &system); !warning.empty()) {
    system.warnings.push_back(warning);
    SayWarnings({warning});
  }
  SolveConfig config = ReadSolveConfig(scene, system);
  if (!o.sampling.empty()) config.sampling = SamplingFromString(o.sampling);
  SolveConfig given;  // natural viewing of this target only, never of the scene's own
  ApplyTargetOption(o.target, given);
  if (o.eyes != "scene" && o.eyes != "both") throw Error("--eyes: \"" + o.eyes + "\" is not scene or both");
  if (o.eyes == "scene" && !o.partner_patterns.empty())
    throw Error("--partner-patterns: the other eye's patterns, for --eyes both");
  const bool both = o.eyes == "both";
  const std::vector<DisplaySystem> eyes = both ? BothEyes(o, system) : std::vector<DisplaySystem>{system};
  AccommodationStates(o);
  CheckMetricOptions(o, eyes, given);
  const std::vector<std::string> written =
      both ? std::vector<std::string>{"left", "right", "index.html"}
           : std::vector<std::string>{"display", "natural", "retina.csv", "index.html"};
  StagedOutput stage(o.out, "retina", written,
                     {{o.scene, "the scene"},
                      {o.patterns, "the patterns"},
                      {o.partner_patterns, "the other eye's patterns"},
                      {given.target, "the target"},
                      {given.target_scene, "the target scene"}});
  double white = 0;
  std::vector<std::vector<RetinaStateResult>> results;
  try {
    for (const DisplaySystem& eye : eyes) {
      given.target_moved_m = TargetSceneMove(eye.eye);  // targets rendered per eye
      const bool own =
          !both || eye.eye.binocular->side == system.eye.binocular->side || eye.eye.binocular->shared_display;
      const std::string side = both ? (eye.eye.binocular->side < 0 ? "left" : "right") : "";
      const std::string folder = both ? stage.staging() + "/" + side : stage.staging();
      if (std::error_code error; both && !std::filesystem::create_directories(folder, error) && error)
        throw Error(folder + ": cannot make the folder: " + error.message());
      results.push_back(RetinaOfEye(o, scene, eye, config, given, own ? o.patterns : o.partner_patterns,
                                    both ? "retina, " + side + " eye" : "retina", folder, &white));
    }
    if (both) WriteBothEyesPage(o, scene, eyes, results, white, !given.target_scene.empty(), stage.staging());
  } catch (const Error& e) {
    throw stage.Explain(e);
  }
  stage.Commit();
  PrintRetinaResult(o, eyes, results, white, !given.target.empty() || !given.target_scene.empty());
}

}  // namespace

void AddRetinaCommand(CLI::App& app) {
  auto o = std::make_shared<RetinaCommandOptions>();
  CLI::App* cmd = app.add_subcommand("retina", "Retinal images of the display (and of the target) over accommodation");
  cmd->add_option("scene", o->scene, "Display scene file (JSON)")->required();
  cmd->add_option("--patterns", o->patterns, "Output folder of `layerlab solve` (its patterns/)")->required();
  cmd->add_option("--accommodation", o->accommodation,
                  "States shown, comma-separated, each a value or a range FROM:TO:STEP: D, or with units (\"1.0 D\", "
                  "\"0.5 m\"; default 0.4,1.0,1.6,2.2)");
  cmd->add_option("--focal-stack", o->focal_stack,
                  "Also scored in retina.csv, a range FROM:TO:STEP: D, e.g. 0:2.6:0.1 or \"0 D:2.6 D:0.1 D\"");
  AddTargetOptions(cmd, o->target, ": natural viewing of it (a scene's traced, not rendered)");
  AddPoseOptions(cmd, o->pose);
  AddOpticsOptions(cmd, o->optics);
  cmd->add_option("--resolution", o->resolution, "Retinal sample size: degrees or \"3 arcmin\" (default 0.05)");
  cmd->add_option("--field", o->field, "Retinal field W,H: degrees (default: the display's field of view)");
  cmd->add_option("--exr", o->exr,
                  "How the images' EXRs store a value: half (16 bits, at most 0.049 % off, half the size: pictures "
                  "to look at; retina.csv comes from the float images) or float (default half)")
      ->check(CLI::IsMember({"half", "float"}));
  cmd->add_option("--sampling", o->sampling,
                  "Layer sampling: nearest or bilinear (default: the scene's solve section)");
  cmd->add_option("--eyes", o->eyes,
                  "scene: the scene's eye; both: it and the other eye of its binocular pair, into OUT/left and "
                  "OUT/right (default scene)");
  cmd->add_option("--partner-patterns", o->partner_patterns,
                  "With --eyes both and a display per eye: the other eye's display's solve folder");
  cmd->add_option("--metrics", o->metrics,
                  "With a target: score each state's display image against natural viewing by these, a retina.csv "
                  "column each: psnr, ssim, ms_ssim, jnd, or all (default psnr; docs/metrics.md)");
  AddMetricSettingFlags(cmd, &o->metric_flags);
  cmd->add_option("--out", o->out, "Output folder")->required();
  cmd->callback([o] { RunRetinaCommand(*o); });
}

}  // namespace layerlab::app
