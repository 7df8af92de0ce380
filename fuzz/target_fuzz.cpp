// Target-scene text -> strict JSON -> a TargetScene (light field, objects, textures, keys) -> the scene posed
// at a few times of its animation (targets/target_motion.h). The meshes it may name are a small OBJ written
// beside it. layerlab::Error is the documented refusal; anything else is a finding.
#include <cstddef>
#include <cstdint>

#include "layerlab/framework/error.h"
#include "layerlab/framework/json_file.h"
#include "layerlab/fuzz/fuzz_util.h"
#include "layerlab/targets/target_scene.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string file = [] {
    const std::string tetrahedron =
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvt 0 0\nvt 1 0\nvt 0 1\n"
        "f 1/1 2/2 3/3\nf 1/1 2/2 4/3\nf 1/1 3/2 4/3\nf 2/1 3/2 4/3\n";
    layerlab::fuzz::WriteBytes(layerlab::fuzz::ScratchDir() / "mesh.obj",
                               reinterpret_cast<const uint8_t*>(tetrahedron.data()), tetrahedron.size());
    return (layerlab::fuzz::ScratchDir() / "target.json").string();
  }();
  try {
    nlohmann::json document = layerlab::ParseJson(layerlab::fuzz::AsString(data, size), file);
    const layerlab::TargetScene scene = layerlab::ParseTarget(document, file);
    for (double time_s : {0.0, 0.25, 1.0, 1e3}) (void)layerlab::TargetSceneAt(scene, time_s);
  } catch (const layerlab::Error&) {
  }
  return 0;
}
