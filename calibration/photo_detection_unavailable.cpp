// photo_detection.h in a build without OpenCV: detection refuses, naming the build option.
#include "layerlab/calibration/photo_detection.h"

namespace layerlab {
namespace {

[[noreturn]] void Refuse() {
  throw Error(
      "this layerlab was built without OpenCV, which detecting the patterns in photographs needs: install "
      "libopencv-calib3d-dev, libopencv-imgproc-dev and libopencv-imgcodecs-dev and configure with "
      "-DLAYERLAB_WITH_OPENCV=ON (docs/calibration.md)");
}

}  // namespace

Photo ReadPhoto(const std::string&, const std::string&) { Refuse(); }

Detection DetectCaptures(const std::string&, const CapturePlan&, const DisplaySystem&,
                         const std::optional<CameraIntrinsics>&, const PhotoCheck&, PhotoFormat) {
  Refuse();
}

}  // namespace layerlab
