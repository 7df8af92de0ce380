// run: the scene's "run" section, what `layerlab run` does beyond the solve
// (docs/run-section.md). Nothing that is not declared is computed. The keys
// of run, run.retina and run.compare are the run option tables'
// (analysis/run_option_table.h), those of run.contrast the contrast option
// table's (analysis/contrast_option_table.h), and so are their references.
//
// depth_range: a range of depths, {"from": ..., "to": ..., "step": ...}, as
// run.retina's focal_stack and run.contrast's accommodation take it.
//
// | key  | type          | default  | meaning                                |
// |------|---------------|----------|----------------------------------------|
// | from | depth         | required | the first state                        |
// | to   | depth         | required | the last state, beyond from            |
// | step | optical power | required | above 0 D and at most to - from        |
#include "layerlab/analysis/run_config.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "layerlab/analysis/contrast_option_table.h"
#include "layerlab/analysis/run_option_table.h"
#include "layerlab/framework/json_file.h"
#include "layerlab/framework/option_reader.h"
#include "layerlab/framework/params.h"
#include "layerlab/framework/units.h"
#include "layerlab/retina/retina.h"
#include "layerlab/solvers/solve_config.h"

namespace layerlab {
namespace {

using nlohmann::json;

constexpr double kMaxDiopters = 20;
constexpr size_t kMaxStates = 1000;

std::vector<std::string> StringList(Params& p, const std::string& key) {
  Params items = ArrayItems(p, key);
  std::vector<std::string> out;
  for (size_t k = 0; items.has(std::to_string(k)); ++k) out.push_back(items.string(std::to_string(k)));
  return out;
}

double RequiredDepth(Params& p, const std::string& key) {
  std::optional<Depth> d = p.optional_depth(key);
  if (!d) p.fail(key, "missing required key \"" + key + "\"");
  return d->diopters;
}

// { "from": depth, "to": depth, "step": "0.1 D" } as the values from, from + step, ... up to to.
std::vector<double> DepthRange(Params& parent, const std::string& key) {
  Params p = parent.object(key);
  double from = RequiredDepth(p, "from"), to = RequiredDepth(p, "to");
  double step = p.quantity("step", Dimension::kOpticalPower);
  p.check_all_read();
  p.require_range("from", from, 0, kMaxDiopters, false, false);
  p.require_range("to", to, 0, kMaxDiopters, false, false);
  if (!(to > from)) p.fail("to", FormatFixed(to, 2) + " D is not beyond \"from\" (" + FormatFixed(from, 2) + " D)");
  if (!(step > 0) || step > to - from)
    p.fail("step", FormatFixed(step, 3) + " D: give a step above 0 and at most to - from (" +
                       FormatFixed(to - from, 2) + " D)");
  if ((to - from) / step > kMaxStates) p.fail("step", "more than " + std::to_string(kMaxStates) + " states");
  std::vector<double> values;
  for (int k = 0;; ++k) {
    double v = from + k * step;
    if (v > to + 1e-9 * step) break;
    values.push_back(v);
  }
  return values;
}

// A section's "metrics": names, comma-separated (metrics/retinal_metrics.h), refused naming the key.
std::vector<const RetinalMetric*> MetricsKey(Params& p) {
  const std::string names = p.string("metrics");
  try {
    return ParseRetinalMetrics(names, "metrics");
  } catch (const Error& e) {
    p.fail("metrics", std::string(e.what()).substr(std::string("metrics: ").size()));
  }
}

// A section's "fovea" ([x, y] angles) and "jnd_minkowski_exponent", refused naming the key.
MetricSettings MetricSettingsKeys(Params& p) {
  MetricSettings s;
  if (p.has("fovea")) {
    const std::array<double, 2> gaze = p.quantity_pair("fovea", Dimension::kAngle, {0, 0});
    s.fovea_deg = std::array<double, 2>{gaze[0] * kDegreesPerRadian, gaze[1] * kDegreesPerRadian};
  }
  if (p.has("jnd_minkowski_exponent")) {
    s.jnd_minkowski_exponent = p.quantity("jnd_minkowski_exponent", Dimension::kFraction);
    p.require_range("jnd_minkowski_exponent", s.jnd_minkowski_exponent, 1, 1e6, false, false);
  }
  return s;
}

RetinaRunConfig ReadRetina(Params& run, const DisplaySystem& system) {
  RetinaRunConfig r;
  r.enabled = true;
  Params p = run.object("retina");
  for (const char* key : {"focal_stack", "field", "metrics", "fovea", "jnd_minkowski_exponent"}) p.mark_read(key);
  for (const VirtualLayer& layer : system.layers)  // the panels' planes, not a backlight's emission
    if (!layer.panel.emitter) r.accommodation_diopters.push_back(layer.diopters);
  ReadOptionEntries(p, RetinaRunOptionTable(), &r);
  if (p.has("focal_stack")) r.focal_stack_diopters = DepthRange(p, "focal_stack");
  if (p.has("metrics")) r.metrics = MetricsKey(p);
  r.metric_settings = MetricSettingsKeys(p);
  if (p.has("field")) {
    const RetinaRunOptionEntry& e = RetinaRunOption("field");
    std::array<double, 2> field = p.quantity_pair("field", Dimension::kAngle, {0, 0});
    r.field_x_deg = field[0] / e.FieldUnitInSI(), r.field_y_deg = field[1] / e.FieldUnitInSI();
    if (!e.range.Contains(r.field_x_deg) || !e.range.Contains(r.field_y_deg))
      p.fail("field", "each angle " + e.Constraint());
  }
  p.check_all_read();
  if (r.states().size() > kMaxStates) p.fail("focal_stack", "more than " + std::to_string(kMaxStates) + " states");
  return r;
}

ContrastRunConfig ReadContrast(Params& run, const Scene& scene) {
  ContrastRunConfig c;
  c.enabled = true;
  ContrastOptions& o = c.options;
  Params p = run.object("contrast");
  for (const char* key : {"accommodation", "scenes", "factorized_for"}) p.mark_read(key);
  ReadOptionEntries(p, ContrastOptionTable(), &o);
  if (p.has("accommodation")) {
    std::vector<double> a = DepthRange(p, "accommodation");
    if (a.size() < 3) p.fail("accommodation", "the sweep needs at least 3 states to find a peak");
    o.accommodation_min_diopters = a.front();
    o.accommodation_max_diopters = a.back();
    o.accommodation_step_diopters = a[1] - a[0];
  }
  CheckRetinaSampling(o.retina_field_deg, 3 * o.retina_resolution_deg, o.retina_resolution_deg,
                      p.where().child("retina_field").str(), p.where().child("retina_resolution").str());
  if (p.has("scenes"))
    for (const std::string& file : StringList(p, "scenes")) c.scenes.push_back(ResolveAgainstScene(scene, file));
  if (p.has("factorized_for")) c.factorized_for = ResolveAgainstScene(scene, p.string("factorized_for"));
  p.check_all_read();
  return c;
}

CompareRunConfig ReadCompare(Params& run, const Scene& scene) {
  CompareRunConfig c;
  c.enabled = true;
  Params p = run.object("compare");
  for (const char* key : {"scenes", "solvers"}) p.mark_read(key);
  if (p.has("scenes"))
    for (const std::string& file : StringList(p, "scenes")) c.scenes.push_back(ResolveAgainstScene(scene, file));
  if (p.has("solvers")) {
    Params items = ArrayItems(p, "solvers");
    for (size_t k = 0; items.has(std::to_string(k)); ++k) {
      const std::string i = std::to_string(k);
      c.solvers.push_back(items.string(i));
      if (!SolverRegistry::Builtins().find(c.solvers.back())) {
        try {
          SolverRegistry::Builtins().create(c.solvers.back());
        } catch (const Error& e) {
          items.fail(i, e.message());
        }
      }
    }
  }
  if (p.has("iterations")) {
    const OptionRange& range = CompareRunOption("iterations").range;
    c.iterations = static_cast<int>(p.integer("iterations", int64_t(range.min), int64_t(range.max)));
  }
  if (p.has("time_budget")) {
    const OptionRange& range = CompareRunOption("time_budget").range;
    c.time_budget_s = p.quantity("time_budget", Dimension::kTime);
    p.require_range("time_budget", *c.time_budget_s, range.min, range.max, range.min_open, range.max_open);
  }
  if (p.has("metrics")) c.metrics = MetricsKey(p);
  c.metric_settings = MetricSettingsKeys(p);
  for (const char* key : {"fovea", "jnd_minkowski_exponent"})
    if (p.has(key) && c.metrics.empty())
      p.fail(key, "sets how the focal stack's metrics are measured: give \"metrics\" too");
  if (p.has("objectives")) {
    p.mark_read("objectives");
    Params items = ArrayItems(p, "objectives");
    for (size_t k = 0; items.has(std::to_string(k)); ++k) {
      const std::string i = std::to_string(k);
      const std::optional<ObjectiveKind> objective = ObjectiveKindNamed(items.string(i));
      if (!objective) items.fail(i, "\"" + items.string(i) + "\" is not one of lightfield or retinal");
      c.objectives.push_back(*objective);
    }
  }
  p.check_all_read();
  return c;
}

FramesRunConfig ReadFrames(Params& run) {
  FramesRunConfig f;
  f.enabled = true;
  Params p = run.object("frames");
  if (!p.has("count")) p.fail("count", "is required: the frames to solve");
  ReadOptionEntries(p, FramesRunOptionTable(), &f);
  p.check_all_read();
  return f;
}

}  // namespace

std::vector<double> RetinaRunConfig::states() const {
  std::vector<double> s = accommodation_diopters;
  s.insert(s.end(), focal_stack_diopters.begin(), focal_stack_diopters.end());
  std::sort(s.begin(), s.end());
  s.erase(std::unique(s.begin(), s.end(), [](double a, double b) { return std::abs(a - b) < 1e-9; }), s.end());
  return s;
}

RunConfig ReadRunConfig(const Scene& scene, const DisplaySystem& system) {
  RunConfig config;
  if (!scene.document.contains("run")) return config;
  config.declared = true;
  Params p(scene.document["run"], {scene.file, "/run"});
  for (const char* key : {"retina", "contrast", "compare", "frames"}) p.mark_read(key);
  if (p.has("retina")) config.retina = ReadRetina(p, system);
  if (p.has("frames")) config.frames = ReadFrames(p);
  if (p.has("contrast")) config.contrast = ReadContrast(p, scene);
  if (p.has("compare")) config.compare = ReadCompare(p, scene);
  ReadOptionEntries(p, RunOptionTable(), &config);
  p.check_all_read();
  return config;
}

}  // namespace layerlab
