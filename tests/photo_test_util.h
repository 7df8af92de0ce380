// What the tests of calibration from photographs share: the examples, a
// small synthetic camera and capture plan, a display as built, and where its
// boards' corners truly appear.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "layerlab/calibration/capture_plan.h"
#include "layerlab/calibration/photo_detection.h"
#include "layerlab/calibration/synthetic_photo.h"
#include "layerlab/tests/calibration_test_util.h"

namespace layerlab::testing {

DisplaySystem Example(const std::string& name);
// An empty folder of that name (and the process id) in the temporary folder.
std::string FreshFolder(const std::string& name);

// A camera that sees the whole of every panel of the examples at a reduced size (CI time): 720 x 420.
PhotoCamera TestCamera();
// The plan's defaults (10 x 6 squares, three positions) with a 9-step luminance ramp.
PlanOptions TestPlan();

// The example scene as built: placements of `truth` (calibration_test_util.h), and its gamma and black level.
DisplaySystem Built(const DisplaySystem& designed, const std::vector<PanelTruth>& truth,
                    const std::vector<OpticTruth>& optics = {});

const VirtualLayer& Layer(const DisplaySystem& s, const std::string& name);
// The plan's `position`-th chessboard capture of `panel`.
const PlannedCapture& ChessboardCapture(const CapturePlan& plan, const std::string& panel, size_t position = 0);
Photo AsPhoto(const Image& image);

// PNG bytes written by hand: the chunk CRC (ISO 3309) and big-endian integers of `bytes` bytes.
uint32_t Crc32(const std::string& bytes);
std::string BigEndian(uint32_t v, int bytes = 4);

// Where the corners of `capture`'s board truly appear: the built display's optics, the camera's intrinsics.
std::vector<std::array<double, 2>> TrueCorners(const DisplaySystem& built, const CapturePlan& plan,
                                               const PlannedCapture& capture, const CameraIntrinsics& camera);

}  // namespace layerlab::testing
