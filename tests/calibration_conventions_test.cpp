// The worked example of docs/calibration.md ("Conventions"): where a camera
// sees one marker of the paper prototype's rear_a, computed by hand from the
// scene's numbers with the stated conventions (pixel centres, rows down the
// panel, rotation about the active region's centre before the offset), against
// the synthetic measurements' construction and the fit's marker model, and
// against the numbers the page prints.
#include <gtest/gtest.h>

#include <cmath>

#include "layerlab/calibration/synthetic_measurements.h"
#include "layerlab/framework/units.h"
#include "layerlab/tests/calibration_test_util.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

TEST(CalibrationConventions, TheWorkedExampleOfTheDocs) {
  const DisplaySystem designed = Compile(LoadScene(testing::ExamplePath("paper_prototype.json")));
  // rear_a offset by (0.3, -0.2) mm and turned by 0.25 deg, at its designed distance.
  const double rotation = 0.25 * kRadiansPerDegree;
  const DisplaySystem built = testing::BuiltSystem(designed, {{"rear_a", 0.0, 0.3e-3, -0.2e-3, rotation}});
  const VirtualLayer& layer = built.layers[0];
  ASSERT_EQ(layer.name, "rear_a");
  ASSERT_FALSE(layer.flip_x || layer.flip_y);

  // By hand: f = 75 mm, eye relief e = 10 mm, 0.4 D: the image 2.49 m before the lens, the panel at
  // s = 1 / (1/f + 1/v), and a ray leaving the pupil's centre at slope u meets it at u B.
  const double f = 75e-3, e = 10e-3, v = 1 / 0.4 - e;
  const double s = 1 / (1 / f + 1 / v);
  const double b = e + s - e * s / f;
  EXPECT_NEAR(layer.panel_distance_m, s, 1e-12);
  // Pixel (739, 349) of the 1280 x 800 grid, whose 400 x 200 active region starts at (440, 300); 117 um pitch;
  // integers are pixel centres, rows count down: from the active region's centre, x right, y up.
  const double x = (739 - 440 + 0.5 - 200) * 117e-6, y = (100 - (349 - 300) - 0.5) * 117e-6;
  EXPECT_NEAR(x, 11.6415e-3, 1e-12);
  EXPECT_NEAR(y, 5.9085e-3, 1e-12);
  // Turned about the active region's centre, then offset.
  const double px = 0.3e-3 + std::cos(rotation) * x - std::sin(rotation) * y;
  const double py = -0.2e-3 + std::sin(rotation) * x + std::cos(rotation) * y;
  // Seen from the pupil's centre, and from a camera 2 mm to the right (parallax over 0.4 D).
  const double tx = px / b, ty = py / b;
  const double cx = tx - 2e-3 * 0.4, cy = ty;
  const std::array<double, 2> centre = ImagedMarker(built, layer, 739, 349, {}, {0, 0});
  const std::array<double, 2> right = ImagedMarker(built, layer, 739, 349, {}, {2e-3, 0});
  EXPECT_NEAR(centre[0], std::atan(tx), 1e-12);
  EXPECT_NEAR(centre[1], std::atan(ty), 1e-12);
  EXPECT_NEAR(right[0], std::atan(cx), 1e-12);
  EXPECT_NEAR(right[1], std::atan(cy), 1e-12);
  const double deg = kDegreesPerRadian;
  std::printf("s = %.4f mm, B = %.4f mm, point (%.4f, %.4f) mm, centre (%.4f, %.4f) deg, 2 mm right (%.4f, %.4f) deg\n",
              1e3 * s, 1e3 * b, 1e3 * px, 1e3 * py, deg * centre[0], deg * centre[1], deg * right[0], deg * right[1]);
  // The numbers docs/calibration.md prints.
  EXPECT_NEAR(1e3 * s, 72.8070, 5e-5);
  EXPECT_NEAR(1e3 * b, 73.0994, 5e-5);
  EXPECT_NEAR(1e3 * px, 11.9156, 5e-5);
  EXPECT_NEAR(1e3 * py, 5.7592, 5e-5);
  EXPECT_NEAR(deg * centre[0], 9.2581, 5e-5);
  EXPECT_NEAR(deg * centre[1], 4.5048, 5e-5);
  EXPECT_NEAR(deg * right[0], 9.2134, 5e-5);
  EXPECT_NEAR(deg * right[1], 4.5048, 5e-5);
}

}  // namespace
}  // namespace layerlab
