// Scene text -> strict JSON -> element nodes -> compiled DisplaySystem -> the
// reports `layerlab info` prints. layerlab::Error is the documented refusal;
// anything else (a crash, a sanitizer report, another exception) is a finding.
#include <cstddef>
#include <cstdint>

#include "layerlab/framework/error.h"
#include "layerlab/framework/json_file.h"
#include "layerlab/fuzz/fuzz_util.h"
#include "layerlab/systems/compile.h"
#include "layerlab/systems/scene.h"
#include "layerlab/systems/system_report.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const layerlab::ElementRegistry registry = layerlab::ElementRegistry::WithBuiltins();
  try {
    nlohmann::json document = layerlab::ParseJson(layerlab::fuzz::AsString(data, size), "scene.json");
    layerlab::Scene scene = layerlab::ParseScene(std::move(document), "scene.json", registry);
    layerlab::DisplaySystem system = layerlab::Compile(scene);
    (void)layerlab::FormatSystemTable(system);
    (void)layerlab::SystemToJson(system).dump();
  } catch (const layerlab::Error&) {
  }
  return 0;
}
