#include "layerlab/design/design_gradient.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <optional>

#include "layerlab/design/design_metrics.h"
#include "layerlab/design/placement_gradient.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/lightfield_io.h"
#include "layerlab/metrics/psnr.h"
#include "layerlab/solvers/objective.h"
#include "layerlab/solvers/solution_writer.h"
#include "layerlab/solvers/solve_config.h"
#include "layerlab/systems/compile.h"

namespace layerlab {
namespace {

namespace fs = std::filesystem;

const ElementRegistry& Builtins() {
  static const ElementRegistry builtins = ElementRegistry::WithBuiltins();
  return builtins;
}

// A job's scene, parsed where its job folder is (its paths are rebased there).
Scene SceneOf(const std::string& out, const SweepJob& job) {
  return ParseScene(job.scene, (fs::path(JobFolder(out, job)) / "scene.json").string(), Builtins());
}

// The five placement fields of each layer, in PlacementGradient's order.
std::vector<std::array<double, 5>> Placement(const DisplaySystem& s) {
  std::vector<std::array<double, 5>> p;
  for (const VirtualLayer& l : s.layers)
    p.push_back({l.diopters, l.eye_from_layer_tan_x, l.eye_from_layer_tan_y, l.tan_pitch_x, l.tan_pitch_y});
  return p;
}

// What the placement gradient does not follow: refused when a variable moves it.
std::string OtherThanPlacement(const DisplaySystem& a, const DisplaySystem& b) {
  if (a.layers.size() != b.layers.size() || a.branches.size() != b.branches.size()) return "the layers or branches";
  for (size_t k = 0; k < a.layers.size(); ++k) {
    const VirtualLayer &x = a.layers[k], &y = b.layers[k];
    if (x.name != y.name || x.cols != y.cols || x.rows != y.rows || x.flip_x != y.flip_x || x.flip_y != y.flip_y ||
        x.rotation_rad != y.rotation_rad)
      return "layer " + x.name + "'s grid (its order, size, flips or rotation)";
    if (x.ray_map || y.ray_map) return "layer " + x.name + " (seen through a real lens)";
    if (x.lenslets || y.lenslets) return "layer " + x.name + " (seen through a lens array)";
  }
  for (size_t i = 0; i < a.branches.size(); ++i) {
    if (a.branches[i].layers != b.branches[i].layers) return "the branches' layers";
    if (a.branches[i].efficiency != b.branches[i].efficiency ||
        a.branches[i].backlight_luminance_cd_m2 != b.branches[i].backlight_luminance_cd_m2)
      return "branch " + std::to_string(i) + "'s light (its efficiency or backlight)";
  }
  return "";
}

}  // namespace

std::string GradientProblem(const DesignSpec& spec) {
  if (spec.objective.size() != 1 || spec.metrics[spec.objective[0].metric].name != "psnr")
    return "the objective must be \"psnr\" alone (the light-field PSNR of the solve)";
  for (const DesignConstraint& c : spec.constraints)
    if (c.metric) return "constraint \"" + c.name + "\" is on a metric, whose gradient is not known";
  const nlohmann::ordered_json& solve = spec.base.contains("solve") ? spec.base["solve"] : nlohmann::ordered_json();
  auto value = [&](const char* key) {
    return solve.is_object() && solve.contains(key) ? solve[key] : nlohmann::ordered_json();
  };
  if (value("sampling") != "bilinear")
    return "the scene's solve must use \"sampling\": \"bilinear\" (with nearest sampling the error is a step "
           "function of a layer's placement)";
  if (value("panel_diffraction") == true || value("lc_response") == true)
    return "the solve's panel_diffraction and lc_response are not in the gradient";
  if (value("objective").is_string() && value("objective") != "lightfield")
    return "the solve must minimize the light-field error (\"objective\": \"lightfield\")";
  if (spec.base.contains("elements") && spec.base["elements"].is_array())
    for (const auto& element : spec.base["elements"])
      if (element.is_object() && element.contains("leds"))
        return "the backlight's LED array is seen through its spread, which the gradient does not follow";
  return "";
}

std::vector<double> PsnrGradient(const DesignSpec& spec, const DesignEvaluator& evaluator, const DesignEvaluation& e) {
  const size_t n = spec.variables.size();
  std::vector<double> gradient(n, 0.0);
  const std::vector<SweepJob> jobs = evaluator.JobsOf(e);
  const std::string& out = evaluator.out();
  // How the compiled layers move with each variable (the same for every target).
  std::vector<std::vector<std::array<double, 5>>> moved(n);
  const DisplaySystem at = Compile(SceneOf(out, jobs.front()));
  for (size_t v = 0; v < n; ++v) {
    // Within the bounds, which may be physical limits (0 D): one-sided at a bound.
    const DesignVariable& var = spec.variables[v];
    const double h = 1e-6 * (var.max - var.min);
    DesignEvaluation plus = e, minus = e;
    plus.x[v] = std::min(var.max, e.x[v] + h);
    minus.x[v] = std::max(var.min, e.x[v] - h);
    const double span = plus.x[v] - minus.x[v];
    const DisplaySystem up = Compile(SceneOf(out, evaluator.JobsOf(plus).front()));
    const DisplaySystem down = Compile(SceneOf(out, evaluator.JobsOf(minus).front()));
    for (const DisplaySystem* s : {&up, &down})
      if (const std::string other = OtherThanPlacement(at, *s); !other.empty())
        throw Error(Location{spec.file, "/variables/" + std::to_string(v)},
                    "the variable \"" + spec.variables[v].name + "\" changes " + other +
                        ", not only where the layers are: the exact gradient covers the layers' placement only");
    const auto p = Placement(up), m = Placement(down);
    moved[v].resize(p.size());
    for (size_t k = 0; k < p.size(); ++k)
      for (int f = 0; f < 5; ++f) moved[v][k][f] = (p[k][f] - m[k][f]) / span;
  }
  for (const SweepJob& job : jobs) {
    // The jobs differ in their target only: the display compiled at x serves them all.
    const DisplaySystem& system = at;
    const SolveConfig config = ReadSolveConfig(SceneOf(out, job), system);
    const fs::path run = fs::path(JobFolder(out, job)) / "out";
    const LightField raw = ReadLightField((run / "target" / "lightfield").string());
    const DisplayModel model(system, raw.geometry, config.sampling);
    SolverReport ignored;
    const std::optional<LightField> prepared = PrepareTarget(model, raw, config.options.target_range, &ignored);
    const LightField& target = prepared ? *prepared : raw;
    const Patterns t = ReadPatterns(model, (run / "solve").string());
    double error = 0;
    const std::vector<LayerPlacementGradient> g = PlacementGradient(model, target, t, &error);
    const double psnr = PsnrDb(error, target.rgb.size());
    const std::optional<double> reported =
        MetricValue(spec.metrics[spec.objective[0].metric], ReadJobState(out, job).results);
    if (!reported || std::abs(psnr - *reported) > 1e-3)
      throw Error("evaluation " + e.id + ": the gradient's PSNR, " + std::to_string(psnr) + " dB, is not the run's" +
                  (reported ? " " + std::to_string(*reported) + " dB" : "") +
                  ": the gradient would be of another error");
    const double scale = -10.0 / std::log(10.0) / error / static_cast<double>(jobs.size());
    for (size_t v = 0; v < n; ++v)
      for (size_t k = 0; k < g.size(); ++k) {
        const std::array<double, 5> dE = {g[k].diopters, g[k].center_tan_x, g[k].center_tan_y, g[k].tan_pitch_x,
                                          g[k].tan_pitch_y};
        for (int f = 0; f < 5; ++f) gradient[v] += scale * dE[f] * moved[v][k][f];
      }
  }
  return gradient;
}

}  // namespace layerlab
