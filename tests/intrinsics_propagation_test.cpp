// The camera's intrinsics' uncertainty carried into the fit
// (calibration/intrinsics_propagation.h): a principal point known to 2 px
// moves every marker by 2 px together, which the panels' offsets take up.
#include <gtest/gtest.h>

#include <cmath>

#include "layerlab/calibration/calibration.h"
#include "layerlab/tests/calibration_test_util.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

TEST(IntrinsicsPropagation, APrincipalPointKnownToTwoPixelsWidensTheOffsets) {
  const DisplaySystem designed = Compile(LoadScene(testing::ExamplePath("paper_prototype.json")));
  const std::vector<testing::PanelTruth> truth = testing::ExampleTruth();
  testing::SyntheticSetup setup = testing::ExampleSetup();
  setup.luminance_codes.clear();
  const Measurements exact = testing::SyntheticMeasurements(testing::BuiltSystem(designed, truth), truth, setup);
  Measurements uncertain = exact;
  uncertain.camera->uncertainty = CameraIntrinsicsUncertainty{};
  uncertain.camera->uncertainty->cx_px = 2;

  CalibratedDisplay display;
  const CalibrationReport a = Calibrate(designed, exact, CalibrationOptions{}, &display);
  const CalibrationReport b = Calibrate(designed, uncertain, CalibrationOptions{}, &display);
  ASSERT_TRUE(a.IsSolutionUsable() && b.IsSolutionUsable()) << a.message << b.message;
  for (const VirtualLayer& layer : designed.layers) {
    const ParameterEstimate *x0 = a.find(layer.name, "offset_x"), *x1 = b.find(layer.name, "offset_x");
    const ParameterEstimate *y0 = a.find(layer.name, "offset_y"), *y1 = b.find(layer.name, "offset_y");
    ASSERT_TRUE(x0 && x1 && y0 && y1 && x0->std_dev && x1->std_dev && y0->std_dev && y1->std_dev);
    EXPECT_EQ(x1->value, x0->value) << "the values stay";
    // 2 px at 3000 px focal length turn every marker by 2/3000 rad; a panel's offset shifts by that on its panel:
    // times |B|, the pupil-to-panel ray transfer's (the panel point a unit of tan-angle reaches).
    const double expected = 2.0 / 3000 * std::abs(layer.transfer.b);
    const double added = std::sqrt(std::pow(*x1->std_dev, 2) - std::pow(*x0->std_dev, 2));
    std::printf("%s: offset_x sd %.5f -> %.5f mm, added %.5f mm, expected %.5f mm\n", layer.name.c_str(),
                1e3 * *x0->std_dev, 1e3 * *x1->std_dev, 1e3 * added, 1e3 * expected);
    EXPECT_NEAR(added / expected, 1.0, 0.1) << layer.name;
    EXPECT_NEAR(*y1->std_dev, *y0->std_dev, 0.01 * *y0->std_dev) << layer.name << ": cx moves x only";
  }
  bool noted = false;
  for (const std::string& n : b.notes) noted = noted || n.find("the camera's intrinsics' uncertainty") == 0;
  EXPECT_TRUE(noted);
}

}  // namespace
}  // namespace layerlab
