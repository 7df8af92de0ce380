#include "layerlab/tests/test_util.h"

#include <cmath>
#include <numbers>
#include <random>

#include "layerlab/framework/json_file.h"
#include "layerlab/framework/units.h"

namespace layerlab::testing {

Patterns RandomPatterns(const DisplayModel& model, unsigned seed, float lo, float hi) {
  Patterns t = model.UniformPatterns(0.5f);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(lo, hi);
  for (LayerPattern& p : t)
    for (float& v : p.rgb) v = u(rng);
  return t;
}

LightField RandomLightField(const LightFieldGeometry& g, unsigned seed) {
  LightField lf(g);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0, 1);
  for (float& v : lf.rgb) v = u(rng);
  return lf;
}

::testing::AssertionResult Close(double actual, double expected, double rel_tol, double abs_tol) {
  double tolerance = std::max(abs_tol, rel_tol * std::abs(expected));
  if (std::abs(actual - expected) <= tolerance) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << actual << " differs from " << expected << " by "
                                       << std::abs(actual - expected) << " (tolerance " << tolerance << ")";
}

std::string ExamplePath(const std::string& name) { return std::string(LAYERLAB_SOURCE_DIR) + "/examples/" + name; }

nlohmann::json ReadExample(const std::string& name) { return ReadJsonFile(ExamplePath(name)); }

DisplaySystem CompileJson(const nlohmann::json& scene, const ElementRegistry& registry, const std::string& file) {
  return Compile(ParseScene(scene, file, registry));
}

DisplaySystem CompileJson(const nlohmann::json& scene, const std::string& file) {
  static const ElementRegistry builtins = ElementRegistry::WithBuiltins();
  return CompileJson(scene, builtins, file);
}

std::string CompileError(const nlohmann::json& scene) {
  try {
    CompileJson(scene);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

nlohmann::json ShrunkExample(const std::string& name, int cols, int rows, int views) {
  nlohmann::json scene = ReadExample(name);
  for (auto& e : scene["elements"]) {
    if (e["type"] == "lc_panel") e["active_region"] = {{"cols", cols}, {"rows", rows}};
    if (e["type"] == "eye") e["views"] = {views, views};
  }
  return scene;
}

nlohmann::json& ElementNamed(nlohmann::json& scene, const std::string& name) {
  for (auto& e : scene["elements"])
    if (e.value("name", "") == name) return e;
  throw std::runtime_error("no element named " + name);
}

LightFieldGeometry WindowGeometry(int cols, int rows, int views) {
  LightFieldGeometry g;
  g.origin_z_m = 1 / 1.3;
  g.window_width_m = 2 * g.origin_z_m * std::tan(5 * kRadiansPerDegree);
  g.window_height_m = 2 * g.origin_z_m * std::tan(3 * kRadiansPerDegree);
  g.window_left_m = -g.window_width_m / 2;
  g.window_top_m = g.window_height_m / 2;
  g.cols = cols, g.rows = rows;
  g.views_x = g.views_y = views;
  return g;
}

OneLayer OneLayerDisplay(const std::string& depth) {
  nlohmann::json scene = ShrunkExample("multiplicative_2layer.json", 64, 48, 3);
  ElementNamed(scene, "lens")["next"] = "rear";
  scene["elements"].erase(2);
  ElementNamed(scene, "rear")["virtual_depth"] = depth;
  OneLayer d;
  d.system = CompileJson(scene);
  d.model = std::make_unique<DisplayModel>(d.system, DisplayLightFieldGeometry(d.system, 1.0));
  d.t = d.model->UniformPatterns(0);
  return d;
}

}  // namespace layerlab::testing
