// run: the scene's "run" section, what `layerlab run` does beyond the solve
// (docs/run-section.md). Nothing that is not declared is computed.
//
// | key              | type    | default | meaning                                          |
// |------------------|---------|---------|--------------------------------------------------|
// | retina           | object  | none    | retinal images over accommodation (run.retina)   |
// | contrast         | object  | none    | contrast against accommodation, Fig. 5 (run.contrast) |
// | compare          | object  | none    | other displays on the same target (run.compare)  |
// | write_lightfield | boolean | false   | the solve also writes the synthesized light field |
//
// run.retina: retinal images over accommodation (needs a target).
//
// | key           | type                      | default                   | meaning                            |
// |---------------|---------------------------|---------------------------|------------------------------------|
// | accommodation | array of depths           | the display's layer depths| states shown as the slider's marks |
// | focal_stack   | {from, to, step}: depth_range | none                      | more states, so that the slider scrubs a focal stack |
// | resolution    | angle                     | 0.05 deg                  | retinal sample size                |
// | field         | [angle, angle] or angle   | the display's field of view | retinal field, centered          |
// | natural       | boolean                   | true                      | also natural viewing of the target, side by side |
// | natural_viewing | string                  | "light field"             | "light field": the eye looks at the target light field, the rays the display is asked to reproduce; "traced": at a target scene itself, traced ray by ray with Embree (finer than the views, seconds per state) |
//
// run.contrast: normalized contrast against accommodation (the paper's Fig. 5);
// needs no target: each display is factorized for a cosine grating at each depth.
//
// | key               | type                       | default                  | meaning                                 |
// |-------------------|----------------------------|--------------------------|-----------------------------------------|
// | depths            | array of depths, above 0 D | ["0.7 D", "1.3 D", "1.9 D"] | grating planes                       |
// | frequencies       | array of angular frequencies | ["2 cpd", "4 cpd"]     | grating frequencies                     |
// | accommodation     | {from, to, step}: depth_range | 0 D to 2.6 D by 0.05 D   | the sweep (at least 3 states)           |
// | retina_resolution | angle                      | 0.01 deg                 | retinal sample size                     |
// | retina_field      | angle                      | 20 deg                   | horizontal, centered                    |
// | strip_rows        | integer                    | 24                       | light-field rows around the axis (the grating is vertical) |
// | scenes            | array of paths             | none                     | more displays in the same sweep         |
//
// run.compare: other displays on the same target (needs a target).
//
// | key         | type                  | default          | meaning                                      |
// |-------------|-----------------------|------------------|----------------------------------------------|
// | scenes      | array of paths        | none             | displays beside this one                     |
// | solvers     | array of solver names | each scene's own | every display runs every solver it suits     |
// | iterations  | integer               | each run's own   | outer iterations of every run                |
// | time_budget | time                  | each run's own   | wall-clock budget of every run               |
// | objectives  | array of strings      | each run's own   | "lightfield", "retinal": each solver runs each objective it minimizes (the retinal one: joint, quasi-newton); with "retinal" every row also records the focal-stack PSNR |
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

#include "layerlab/framework/json_file.h"
#include "layerlab/framework/params.h"
#include "layerlab/framework/units.h"
#include "layerlab/retina/retina.h"
#include "layerlab/solvers/solve_config.h"

namespace layerlab {
namespace {

using nlohmann::json;

constexpr double kMaxDiopters = 20;
constexpr size_t kMaxStates = 1000;

// The items of a non-empty array as a Params keyed "0", "1", ... at the
// array's own location, so that an item's error names /.../key/3.
Params ArrayItems(Params& p, const std::string& key) {
  const json& a = p.raw(key);
  if (!a.is_array() || a.empty()) p.fail(key, "expected a non-empty array, got " + JsonKindName(a));
  json items = json::object();
  for (size_t k = 0; k < a.size(); ++k) items[std::to_string(k)] = a[k];
  return Params(std::move(items), p.where(key));
}

// Depths in D ("0.4 D" or "2.5 m"), each in [min, kMaxDiopters].
std::vector<double> DepthList(Params& p, const std::string& key, double min, bool min_open) {
  Params items = ArrayItems(p, key);
  std::vector<double> out;
  for (size_t k = 0; items.has(std::to_string(k)); ++k) {
    const std::string i = std::to_string(k);
    double d = items.optional_depth(i)->diopters;
    items.require_range(i, d, min, kMaxDiopters, min_open, false);
    out.push_back(d);
  }
  return out;
}

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

RetinaRunConfig ReadRetina(Params& run, const DisplaySystem& system) {
  RetinaRunConfig r;
  r.enabled = true;
  Params p = run.object("retina");
  for (const char* key : {"accommodation", "focal_stack", "field"}) p.mark_read(key);
  if (p.has("accommodation")) {
    r.accommodation = DepthList(p, "accommodation", 0, false);
  } else {
    for (const VirtualLayer& layer : system.layers) r.accommodation.push_back(layer.diopters);
  }
  if (p.has("focal_stack")) r.focal_stack = DepthRange(p, "focal_stack");
  r.resolution = p.quantity("resolution", Dimension::kAngle, r.resolution * kRadiansPerDegree) / kRadiansPerDegree;
  p.require_range("resolution", r.resolution, 0, 10, true, true);
  if (p.has("field")) {
    std::array<double, 2> field = p.quantity_pair("field", Dimension::kAngle, {0, 0});
    r.field_x = field[0] / kRadiansPerDegree, r.field_y = field[1] / kRadiansPerDegree;
    if (!(r.field_x > 0 && r.field_x < 170 && r.field_y > 0 && r.field_y < 170))
      p.fail("field", "each angle must lie in (0, 170) deg");
  }
  r.natural = p.boolean("natural", r.natural);
  const std::string viewing = p.string("natural_viewing", "light field");
  if (viewing == "traced")
    r.natural_traced = true;
  else if (viewing != "light field")
    p.fail("natural_viewing", "must be \"light field\" or \"traced\", got \"" + viewing + "\"");
  p.check_all_read();
  if (r.states().size() > kMaxStates) p.fail("focal_stack", "more than " + std::to_string(kMaxStates) + " states");
  return r;
}

ContrastRunConfig ReadContrast(Params& run, const Scene& scene) {
  ContrastRunConfig c;
  c.enabled = true;
  ContrastOptions& o = c.options;
  Params p = run.object("contrast");
  for (const char* key : {"depths", "frequencies", "accommodation", "scenes"}) p.mark_read(key);
  if (p.has("depths")) o.target_diopters = DepthList(p, "depths", 0, true);
  if (p.has("frequencies")) {
    Params items = ArrayItems(p, "frequencies");
    o.frequencies.clear();
    for (size_t k = 0; items.has(std::to_string(k)); ++k) {
      const std::string i = std::to_string(k);
      o.frequencies.push_back(items.quantity(i, Dimension::kAngularFrequency));
      items.require_range(i, o.frequencies.back(), 0, 1000, true, false);
    }
  }
  if (p.has("accommodation")) {
    std::vector<double> a = DepthRange(p, "accommodation");
    if (a.size() < 3) p.fail("accommodation", "the sweep needs at least 3 states to find a peak");
    o.accommodation_min = a.front();
    o.accommodation_max = a.back();
    o.accommodation_step = a[1] - a[0];
  }
  o.retina_resolution =
      p.quantity("retina_resolution", Dimension::kAngle, o.retina_resolution * kRadiansPerDegree) / kRadiansPerDegree;
  p.require_range("retina_resolution", o.retina_resolution, 0, 1, true, false);
  o.retina_field =
      p.quantity("retina_field", Dimension::kAngle, o.retina_field * kRadiansPerDegree) / kRadiansPerDegree;
  p.require_range("retina_field", o.retina_field, 0, 170, true, true);
  CheckRetinaSampling(o.retina_field, 3 * o.retina_resolution, o.retina_resolution,
                      p.where().child("retina_field").str(), p.where().child("retina_resolution").str());
  o.strip_rows = static_cast<int>(p.integer("strip_rows", 1, 100000, o.strip_rows));
  if (p.has("scenes"))
    for (const std::string& file : StringList(p, "scenes")) c.scenes.push_back(ResolveAgainstScene(scene, file));
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
  if (p.has("iterations")) c.iterations = static_cast<int>(p.integer("iterations", 1, 1000000));
  if (p.has("time_budget")) {
    c.time_budget = p.quantity("time_budget", Dimension::kTime);
    p.require_range("time_budget", *c.time_budget, 0, 1e7, true, false);
  }
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

}  // namespace

std::vector<double> RetinaRunConfig::states() const {
  std::vector<double> s = accommodation;
  s.insert(s.end(), focal_stack.begin(), focal_stack.end());
  std::sort(s.begin(), s.end());
  s.erase(std::unique(s.begin(), s.end(), [](double a, double b) { return std::abs(a - b) < 1e-9; }), s.end());
  return s;
}

RunConfig ReadRunConfig(const Scene& scene, const DisplaySystem& system) {
  RunConfig config;
  if (!scene.document.contains("run")) return config;
  config.declared = true;
  Params p(scene.document["run"], {scene.file, "/run"});
  for (const char* key : {"retina", "contrast", "compare"}) p.mark_read(key);
  if (p.has("retina")) config.retina = ReadRetina(p, system);
  if (p.has("contrast")) config.contrast = ReadContrast(p, scene);
  if (p.has("compare")) config.compare = ReadCompare(p, scene);
  config.write_lightfield = p.boolean("write_lightfield", false);
  p.check_all_read();
  return config;
}

}  // namespace layerlab
