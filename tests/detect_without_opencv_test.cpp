// A build without OpenCV refuses detection and names the build option (this
// test links the version of photo_detection.h such a build has).
#include <gtest/gtest.h>

#include "layerlab/calibration/photo_detection.h"

namespace layerlab {
namespace {

TEST(DetectWithoutOpenCVTest, RefusesNamingTheBuildOption) {
  try {
    DetectCaptures("captures", CapturePlan{}, DisplaySystem{}, std::nullopt);
    FAIL() << "detection ran without OpenCV";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("-DLAYERLAB_WITH_OPENCV=ON"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("built without OpenCV"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace layerlab
