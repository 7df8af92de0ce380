// Capture plans (captures.json, what `detect` and `photograph` read): strict
// JSON, then ParseCapturePlan, then what the commands derive from a plan
// without a scene: the JSON written back, the pattern files, each chessboard's
// corners. Built only with LAYERLAB_WITH_CERES (the calibration library).
#include <cstddef>
#include <cstdint>

#include "layerlab/calibration/capture_plan.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/json_file.h"
#include "layerlab/fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    const nlohmann::json document = layerlab::ParseJson(layerlab::fuzz::AsString(data, size), "captures.json");
    const layerlab::CapturePlan plan = layerlab::ParseCapturePlan(document, "captures.json");
    (void)layerlab::CapturePlanToJson(plan).dump();
    (void)layerlab::PatternFiles(plan);
    for (const layerlab::Chessboard& board : plan.chessboards) {
      (void)board.corner(board.corners_x() - 1, board.corners_y() - 1);
      (void)board.dark(board.left + board.square_pixels, board.top);
    }
  } catch (const layerlab::Error&) {
  }
  return 0;
}
