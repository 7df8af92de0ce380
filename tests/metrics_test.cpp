// The perceptual metrics (metrics/) on cases with closed forms; their
// agreement with scikit-image is python/tests/test_metrics.py's.
#include <gtest/gtest.h>

#include <cmath>

#include "layerlab/framework/error.h"
#include "layerlab/metrics/ssim.h"

namespace layerlab {
namespace {

Plane Constant(int width, int height, double value) {
  return {width, height, std::vector<double>(static_cast<size_t>(width) * height, value)};
}

// Two constant images have no structure: cs = (0 + C2) / (0 + C2) = 1 everywhere, and
// SSIM = l = (2ab + C1) / (a^2 + b^2 + C1), C1 = (0.01 R)^2; MS-SSIM = l^0.1333.
TEST(Ssim, ConstantImagesGiveTheLuminanceTermByHand) {
  const double a = 0.3, b = 0.6, c1 = 1e-4;
  const double l = (2 * a * b + c1) / (a * a + b * b + c1);
  EXPECT_NEAR(Ssim(Constant(40, 30, a), Constant(40, 30, b), 1.0), l, 1e-12);
  EXPECT_NEAR(MsSsim(Constant(180, 200, a), Constant(180, 200, b), 1.0), std::pow(l, 0.1333), 1e-12);
  EXPECT_DOUBLE_EQ(Ssim(Constant(40, 30, a), Constant(40, 30, a), 1.0), 1.0);
}

// An image against its negative about its mean: mu equal, s_xy = -s^2, so cs = (C2 - 2 s^2) / (2 s^2 + C2) in
// the interior, where a +-d checkerboard has s^2 = d^2 (the window's weights sum to 1).
TEST(Ssim, ACheckerboardAgainstItsNegativeByHand) {
  const int n = 40;
  const double m = 0.5, d = 0.2, c2 = 9e-4;
  Plane x = Constant(n, n, m), y = Constant(n, n, m);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double s = (i + j) % 2 ? d : -d;
      x.values[static_cast<size_t>(i) * n + j] = m + s, y.values[static_cast<size_t>(i) * n + j] = m - s;
    }
  // The local mean of the checkerboard is not exactly m (the Gaussian's weights on the two colours differ
  // slightly); the luminance term stays 1 to within 1e-6 and s^2 within 1e-3 of d^2.
  EXPECT_NEAR(Ssim(x, y, 1.0), (c2 - 2 * d * d) / (2 * d * d + c2), 2e-3);
}

TEST(Ssim, EncodedLuminanceIsTheSrgbCurveOfRec709Luminance) {
  Image image{2, 1, {"R", "G", "B"}, {0.5f, 0.5f, 0.5f, 0.002f, 0.0f, 0.0f}};
  const Plane p = EncodedLuminance(image);
  EXPECT_NEAR(p.values[0], 1.055 * std::pow(0.5, 1 / 2.4) - 0.055, 1e-7);  // Y = 0.5 (the weights sum to 1)
  EXPECT_NEAR(p.values[1], 12.92 * 0.2126 * 0.002, 1e-9);                  // below 0.0031308: linear
  image.pixels[0] = -0.1f;
  EXPECT_THROW(EncodedLuminance(image), Error);
}

TEST(Ssim, BadInputsAreRefusedNamingWhat) {
  const Plane a = Constant(20, 20, 0.5);
  auto message = [](auto f) {
    try {
      f();
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message([&] { Ssim(a, Constant(20, 21, 0.5), 1); }).find("differ in size"), std::string::npos);
  EXPECT_NE(message([&] { Ssim(Constant(10, 20, 0.5), Constant(10, 20, 0.5), 1); }).find("at least 11"),
            std::string::npos);
  EXPECT_NE(message([&] { MsSsim(a, a, 1); }).find("at least 176"), std::string::npos);
  EXPECT_NE(message([&] { Ssim(a, a, -1); }).find("data range"), std::string::npos);
  Plane nan = a;
  nan.values[7] = NAN;
  EXPECT_NE(message([&] { Ssim(a, nan, 1); }).find("not finite"), std::string::npos);
}

}  // namespace
}  // namespace layerlab
