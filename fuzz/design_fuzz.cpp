// The design file (design/design_spec.h): the input is written as design.json
// into a per-process scratch folder beside a fixed base scene (the
// multiplicative 2-layer example with a target light field), read by
// ReadDesignSpec, its linear constraints checked for a design that meets them
// (CheckDesignFeasible, NLopt's COBYLA), and its starting design's job made in
// memory (nothing is written, nothing runs).
#include <cstddef>
#include <cstdint>

#include "layerlab/design/design_evaluator.h"
#include "layerlab/design/design_search.h"
#include "layerlab/design/design_starts.h"
#include "layerlab/framework/error.h"
#include "layerlab/fuzz/fuzz_util.h"

namespace {

constexpr const char* kBaseScene =
    R"json({"format": "layerlab-scene/1", "name": "base", "elements": [
  {"type": "eye", "name": "eye", "pupil_diameter": "4 mm", "pupil_shape": "square", "pupil_samples": [9, 9], "eye_relief": "1 cm", "accommodation_range": ["0 D", "2.6 D"], "eyebox": ["6 mm", "6 mm"], "views": [13, 13], "next": "lens"},
  {"type": "thin_lens", "name": "lens", "focal_length": "75 mm", "clear_aperture": "50.8 mm", "next": "front"},
  {"type": "lc_panel", "name": "front", "virtual_depth": "2.2 D", "pixel_pitch": "117 um", "resolution": [1280, 800], "active_region": {"cols": 400, "rows": 200}, "max_transmittance": 0.3, "gamma": 2.4, "reversed": true, "next": "rear"},
  {"type": "lc_panel", "name": "rear", "virtual_depth": "0.4 D", "pixel_pitch": "117 um", "resolution": [1280, 800], "active_region": {"cols": 400, "rows": 200}, "max_transmittance": 0.3, "gamma": 2.4, "next": "backlight"},
  {"type": "backlight", "name": "backlight", "luminance": "250 cd/m2"}],
 "solve": {"target": "lf", "iterations": 2}})json";

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto& folder = layerlab::fuzz::ScratchDir();
  static const bool scene_written = [&] {
    const std::string scene = kBaseScene;
    layerlab::fuzz::WriteBytes(folder / "scene.json", reinterpret_cast<const uint8_t*>(scene.data()), scene.size());
    return true;
  }();
  (void)scene_written;
  layerlab::fuzz::WriteBytes(folder / "design.json", data, size);
  try {
    const layerlab::DesignSpec spec = layerlab::ReadDesignSpec((folder / "design.json").string());
    layerlab::CheckDesignFeasible(spec);
    layerlab::DesignEvaluator evaluator(spec, (folder / "out").string());
    layerlab::DesignEvaluation start;
    start.id = "e0000";
    for (const layerlab::DesignVariable& v : spec.variables) start.x.push_back(v.start);
    const std::vector<layerlab::SweepJob> jobs = evaluator.JobsOf(start);
    if (jobs.size() != std::max<size_t>(1, spec.targets.size())) __builtin_trap();
    (void)evaluator.SceneWith(start.x);
    if (spec.optimizer.global == "multistart") {
      // The starts: as many as asked, each within the bounds and the linear constraints.
      const std::vector<std::vector<double>> points = layerlab::MultistartPoints(spec);
      if (points.size() != static_cast<size_t>(spec.optimizer.starts)) __builtin_trap();
      int budget = 0;
      for (int k = 0; k < spec.optimizer.starts; ++k) budget += layerlab::StartBudget(spec, k);
      if (budget != spec.optimizer.evaluations) __builtin_trap();
      for (const std::vector<double>& x : points) {
        if (!layerlab::MeetsLinearConstraints(spec, x)) __builtin_trap();
        for (size_t k = 0; k < x.size(); ++k)
          if (!(x[k] >= spec.variables[k].min && x[k] <= spec.variables[k].max)) __builtin_trap();
      }
    }
  } catch (const layerlab::Error&) {
  }
  return 0;
}
