// Calibration measurements: strict JSON, then ParseMeasurements (the reader
// behind `layerlab fit`). Built only with LAYERLAB_WITH_CERES.
#include <cstddef>
#include <cstdint>

#include "layerlab/calibration/measurements.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/json_file.h"
#include "layerlab/fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    nlohmann::json document = layerlab::ParseJson(layerlab::fuzz::AsString(data, size), "measurements.json");
    (void)layerlab::ParseMeasurements(document, "measurements.json");
  } catch (const layerlab::Error&) {
  }
  return 0;
}
