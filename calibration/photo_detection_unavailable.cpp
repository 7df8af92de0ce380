// photo_detection.h and camera_calibration.h in a build without OpenCV: detection and the
// camera's calibration refuse, naming the build option.
#include "layerlab/calibration/camera_calibration.h"
#include "layerlab/calibration/photo_detection.h"

namespace layerlab {
namespace {

[[noreturn]] void Refuse() {
  throw Error(
      "this layerlab was built without OpenCV, which detecting the patterns in photographs and calibrating the camera "
      "need: install "
      "libopencv-calib3d-dev, libopencv-imgproc-dev and libopencv-imgcodecs-dev and configure with "
      "-DLAYERLAB_WITH_OPENCV=ON (docs/calibration.md)");
}

}  // namespace

IntrinsicsEstimate EstimateIntrinsics(const std::string&, const CameraCapturePlan&, const PhotoCheck&) { Refuse(); }

IntrinsicsEstimate CalibrateFromViews(const PrintedChessboard&, std::vector<BoardView>, int, int) { Refuse(); }

Photo ReadPhoto(const std::string&, const std::string&) { Refuse(); }

Detection DetectCaptures(const std::string&, const CapturePlan&, const DisplaySystem&,
                         const std::optional<CameraIntrinsics>&, const PhotoCheck&, PhotoFormat) {
  Refuse();
}

}  // namespace layerlab
