#include "layerlab/bench/bench_setup.h"

#include <sys/resource.h>

#include <filesystem>
#include <map>
#include <random>

#include "layerlab/framework/json_file.h"
#include "layerlab/framework/lightfield_io.h"
#include "layerlab/kernels/synthesis.h"
#include "layerlab/systems/compile.h"
#include "layerlab/systems/scene.h"

namespace layerlab::bench {

BenchSettings& Settings() {
  static BenchSettings settings;
  return settings;
}

namespace {

// A target the display can show exactly: random smooth patterns synthesized
// through the display itself, so that solvers converge as on real content.
LightField SyntheticTarget(const DisplayModel& model) {
  Patterns t = model.UniformPatterns(0.5f);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0.2f, 0.9f);
  for (LayerPattern& p : t)
    for (float& v : p.rgb) v = u(rng);
  return Synthesize(model, t);
}

}  // namespace

const Workload& GetWorkload(const std::string& example, int subframes) {
  static std::map<std::pair<std::string, int>, std::unique_ptr<Workload>> cache;
  auto& slot = cache[{example, subframes}];
  if (slot) return *slot;
  slot = std::make_unique<Workload>();
  Workload& w = *slot;
  const std::string path = std::string(LAYERLAB_SOURCE_DIR) + "/examples/" + example + ".json";
  if (subframes == 1) {
    w.system = Compile(LoadScene(path));
  } else {
    nlohmann::json scene = ReadJsonFile(path);
    scene["subframes"] = subframes;
    w.system = Compile(ParseScene(scene, path, ElementRegistry::WithBuiltins()));
  }
  const std::string dice = std::string(LAYERLAB_DATA_DIR) + "/dice";
  if (!Settings().smoke && std::filesystem::exists(dice + "/lightfield.json")) {
    w.target = ReadLightField(dice, {.load_depth = false});
    w.target_name = "dice";
    w.model = std::make_unique<DisplayModel>(w.system, w.target.geometry);
    return w;
  }
  LightFieldGeometry g = DisplayLightFieldGeometry(w.system, 1.3);
  if (Settings().smoke) {
    g.cols = 40, g.rows = 20, g.views_x = g.views_y = 3;
    for (VirtualLayer& layer : w.system.layers) {
      layer.cols = 40, layer.rows = 20;
      layer.tan_pitch_x *= 10, layer.tan_pitch_y *= 10;
    }
  }
  w.model = std::make_unique<DisplayModel>(w.system, g);
  w.target = SyntheticTarget(*w.model);
  w.target_name = "synthetic";
  return w;
}

double PeakRssMb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0;  // kB on Linux
}

}  // namespace layerlab::bench
