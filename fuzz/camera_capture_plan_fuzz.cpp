// Camera capture plans (camera_captures.json, what `camera-intrinsics` and
// `photograph` read): strict JSON, then ParseCameraCapturePlan, then the JSON
// written back and, for a board of a reasonable size, its image to print.
// Built only with LAYERLAB_WITH_CERES (the calibration library).
#include <cstddef>
#include <cstdint>

#include "layerlab/calibration/camera_capture_plan.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/json_file.h"
#include "layerlab/fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    const nlohmann::json document = layerlab::ParseJson(layerlab::fuzz::AsString(data, size), "camera_captures.json");
    const layerlab::CameraCapturePlan plan = layerlab::ParseCameraCapturePlan(document, "camera_captures.json");
    (void)layerlab::CameraCapturePlanToJson(plan).dump();
    if (static_cast<int64_t>(plan.board.image_width()) * plan.board.image_height() <= 4 << 20)
      (void)layerlab::PrintedChessboardImage(plan.board);
  } catch (const layerlab::Error&) {
  }
  return 0;
}
