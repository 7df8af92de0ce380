// The sweep file (analysis/sweep_spec.h): the input is written as sweep.json
// into a per-process scratch folder beside a fixed base scene (the
// multiplicative 2-layer example with a target light field and a compared
// scene, so that path values are rebased), read by ReadSweepSpec and expanded
// by ExpandSweep in memory (nothing is written). The grid's size is checked
// arithmetic: 64 parameters of 2 values must be refused, not wrap to 0.
// Grids of more than 2000 points are read but not expanded (each job holds a
// copy of the scene; 100000 of them is a memory test, not a parser's).
#include <cstddef>
#include <cstdint>

#include "layerlab/analysis/slurm_resources.h"
#include "layerlab/analysis/sweep_jobs.h"
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
 "solve": {"target": "lf", "iterations": 2}, "run": {"contrast": {"scenes": ["other.json"]}}})json";

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto& folder = layerlab::fuzz::ScratchDir();
  static const bool scene_written = [&] {
    const std::string scene = kBaseScene;
    layerlab::fuzz::WriteBytes(folder / "scene.json", reinterpret_cast<const uint8_t*>(scene.data()), scene.size());
    return true;
  }();
  (void)scene_written;
  layerlab::fuzz::WriteBytes(folder / "sweep.json", data, size);
  try {
    const layerlab::SweepSpec spec = layerlab::ReadSweepSpec((folder / "sweep.json").string());
    (void)layerlab::SlurmJobNameProblem(spec.name);
    if (spec.job_count() <= 2000) {
      const std::vector<layerlab::SweepJob> jobs = layerlab::ExpandSweep(spec, (folder / "out").string());
      if (jobs.size() != spec.job_count()) __builtin_trap();
    }
  } catch (const layerlab::Error&) {
  }
  return 0;
}
