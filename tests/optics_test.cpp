// Eq. 1 and 2 against independent computations: the Gaussian lens formula
// worked by hand, and paraxial rays traced through a thin lens.
#include <cmath>
#include <numbers>

#include "layerlab/systems/optics.h"
#include "layerlab/systems/ray_transfer.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

using testing::Close;

constexpr double f = 0.075, e = 0.01;

// Traces two rays from a panel point (height h, distance s behind the lens)
// toward the eye through a thin lens, and intersects their backward
// extensions: the virtual image's eye-space depth and height.
struct TracedImage {
  double depth, height;
};
TracedImage TraceVirtualImage(double s, double h) {
  double slopes[2] = {0.0, 0.02};  // dy per unit of travel toward the eye
  double at_lens[2], after[2];
  for (int i = 0; i < 2; ++i) {
    at_lens[i] = h + slopes[i] * s;
    after[i] = slopes[i] - at_lens[i] / f;  // thin-lens refraction
  }
  // After the lens, y(z) = at_lens + after * (e - z); equal heights at:
  double e_minus_z = (at_lens[1] - at_lens[0]) / (after[0] - after[1]);
  return {e - e_minus_z, at_lens[0] + after[0] * e_minus_z};
}

TEST(Optics, FloatPanelMatchesTracedRays) {
  for (double s : {0.02, 0.05, 0.06417, 0.07281, 0.0749}) {
    TracedImage traced = TraceVirtualImage(s, 1e-3);
    FloatedImage image = FloatPanel(s, f, e);
    EXPECT_TRUE(Close(image.depth_m, traced.depth, 1e-9)) << "s = " << s;
    EXPECT_TRUE(Close(image.diopters, 1.0 / traced.depth, 1e-9));
    EXPECT_TRUE(Close(image.magnification, traced.height / 1e-3, 1e-9));
    EXPECT_TRUE(Close(image.tan_per_meter, traced.height / 1e-3 / traced.depth, 1e-9));
  }
}

TEST(Optics, PaperTable1ByTheLensFormula) {
  // Gaussian formula for a virtual image d behind the lens: 1/s = 1/f + 1/d, z = d + e.
  const double diopters[] = {0.4, 1.0, 1.6, 2.2};
  const double distance_mm[] = {72.81, 69.72, 66.85, 64.17};  // lightfield-format.md
  const double magnification[] = {34.2, 14.2, 9.2, 6.93};
  for (int k = 0; k < 4; ++k) {
    double d = 1.0 / diopters[k] - e;
    double s = 1.0 / (1.0 / f + 1.0 / d);
    EXPECT_TRUE(Close(PanelDistanceForDiopters(diopters[k], f, e), s, 1e-12));
    EXPECT_TRUE(Close(s * 1e3, distance_mm[k], 0, 0.005));
    FloatedImage image = FloatPanel(s, f, e);
    EXPECT_TRUE(Close(image.diopters, diopters[k], 1e-12));
    EXPECT_TRUE(Close(image.magnification, d / s, 1e-12));
    EXPECT_TRUE(Close(image.magnification, magnification[k], 0, 0.01));
  }
}

TEST(Optics, FieldOfViewEq2) {
  // Farthest layer: M p = 34.2 x 117 um at z = 2.5 m over 400 x 200 pixels.
  double tan_pitch = 34.2 * 117e-6 / 2.5;
  double deg = 180 / std::numbers::pi;
  EXPECT_TRUE(Close(FieldOfView(tan_pitch, 400) * deg, 2 * std::atan(34.2 * 117e-6 * 400 / (2 * 2.5)) * deg, 1e-12));
  EXPECT_TRUE(Close(FieldOfView(tan_pitch, 400) * deg, 35.5, 0, 0.05));
  EXPECT_TRUE(Close(FieldOfView(tan_pitch, 200) * deg, 18.2, 0, 0.05));
  // One pixel subtends atan(4.0 mm / 2.5 m) = 0.0917 deg: 5.45 cycles per degree.
  EXPECT_TRUE(Close(NyquistCyclesPerDegree(tan_pitch), 1 / (2 * std::atan(tan_pitch) * deg), 1e-12));
  EXPECT_TRUE(Close(NyquistCyclesPerDegree(tan_pitch), 5.45, 0, 0.01));
}

TEST(Optics, FocalPlaneIsInfinityWithoutNaN) {
  FloatedImage image = FloatPanel(f, f, e);
  EXPECT_EQ(image.diopters, 0.0);
  EXPECT_TRUE(std::isinf(image.depth_m));
  EXPECT_TRUE(std::isinf(image.magnification));
  EXPECT_TRUE(Close(image.tan_per_meter, 1 / f, 1e-15));  // a pixel subtends p / f
  EXPECT_EQ(PanelDistanceForDiopters(0.0, f, e), f);
  // Continuity: just inside the focal plane the angular scale tends to 1/f.
  EXPECT_TRUE(Close(FloatPanel(f * (1 - 1e-9), f, e).tan_per_meter, 1 / f, 1e-6));
}

// `then` composes in path order: a ray meets this transfer first, then `next`. Checked against the ray traced
// element by element by hand (y' = y + t u through a gap, u' = u - P y through a lens), where the order matters.
TEST(Optics, ThenAppliesThisTransferFirstAsTheRayMeetsIt) {
  const RayTransfer<double> first = RayTransfer<double>().then_gap(0.03).then_power(1 / 0.075);
  const RayTransfer<double> second = RayTransfer<double>().then_gap(0.02).then_power(-5.0);
  const RayTransfer<double> both = first.then(second);
  double y = 0.002, u = 0.1;  // m, slope
  const double y0 = y, u0 = u;
  y += 0.03 * u;
  u -= y / 0.075;
  y += 0.02 * u;
  u -= -5.0 * y;
  EXPECT_NEAR(both.a * y0 + both.b * u0, y, 1e-15);
  EXPECT_NEAR(both.c * y0 + both.d * u0, u, 1e-14);
  const RayTransfer<double> reversed = second.then(first);
  EXPECT_GT(std::abs(reversed.a * y0 + reversed.b * u0 - y), 1e-5) << "the example does not tell the orders apart";
}

}  // namespace
}  // namespace layerlab
