// The perceptual metrics (metrics/) on cases with closed forms; their
// agreement with scikit-image is python/tests/test_metrics.py's.
#include <gtest/gtest.h>

#include <cmath>

#include "layerlab/eye/barten_csf.h"
#include "layerlab/framework/error.h"
#include "layerlab/metrics/csf_jnd.h"
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

// Barten's CSF against the values colour-science's implementation of it
// documents (colour.contrast, barten1999.py doctests): the pupil for 100
// cd/m2 on a 60 x 60 deg field, the retinal illuminance of 100 cd/m2 through
// 2.1 mm, S at 4 cpd for 20 cd/m2 through 2.1 mm on 60 deg, and the minimum
// detectable contrast 2 / (1.27 S_max) of ITU-R BT.2246-4's Figure 31 at 0.01
// and 100 cd/m2 (S_max over frequency, Barten's pupil on a 60 deg field).
TEST(BartenCsf, TheValuesColourScienceDocuments) {
  EXPECT_NEAR(BartenPupilDiameterMm({100, 60, 60, std::nullopt}), 2.0777571, 1e-7);
  EXPECT_NEAR(RetinalIlluminanceTrolands(100, 2.1), 330.4115803, 1e-7);
  EXPECT_NEAR(BartenContrastSensitivity(4, {20, 60, 60, 2.1}), 360.8691122, 1e-7);
  auto minimum_detectable = [](double luminance) {
    double best = 0;
    for (double u = 0.01; u < 30; u += 0.0005)
      best = std::max(best, BartenContrastSensitivity(u, {luminance, 60, 60, {}}));
    return 2 / (1.27 * best);
  };
  EXPECT_NEAR(minimum_detectable(0.01), 0.0207396, 2e-7);
  EXPECT_NEAR(minimum_detectable(100), 0.0022897, 2e-7);
  EXPECT_EQ(BartenContrastSensitivity(0, {}), 0);
  EXPECT_THROW(BartenContrastSensitivity(4, {-1, 60, 60, {}}), Error);
}

// A grating of contrast c = 1 / S(f) on a uniform field (its threshold) against the field: 1 JND, for any
// Minkowski exponent, across 1-20 cpd and 1-100 cd/m2; at half its threshold 0.5; a uniform change 0.
TEST(CsfJnd, AGratingAtItsThresholdIsOneJnd) {
  const int cols = 240, rows = 64, cycles = 12;
  for (const double luminance : {1.0, 10.0, 100.0})
    for (const double cpd : {1.0, 2.0, 4.0, 8.0, 16.0, 20.0}) {
      CsfJndOptions options;
      options.pixel_deg = cycles / (cpd * cols);
      const double threshold =
          1 / BartenContrastSensitivity(cpd, {luminance, cols * options.pixel_deg, rows * options.pixel_deg, {}});
      Plane field = Constant(cols, rows, luminance), grating = field, half = field;
      for (int i = 0; i < rows; ++i)
        for (int j = 0; j < cols; ++j) {
          const double s = std::sin(2 * M_PI * cycles * j / cols);
          grating.values[static_cast<size_t>(i) * cols + j] = luminance * (1 + threshold * s);
          half.values[static_cast<size_t>(i) * cols + j] = luminance * (1 + 0.5 * threshold * s);
        }
      // The pooling's scale is the continuous sine's; a sampled sine's mean of |sin|^beta equals it for beta 2
      // and 4 (20 samples a period), and for beta 1 is 0.1 cot(pi / 20) against 2 / pi.
      for (const double beta : {1.0, 2.0, 4.0}) {
        options.minkowski_exponent = beta;
        const double sampled = beta == 1 ? 0.1 / std::tan(M_PI / 20) / (2 / M_PI) : 1.0;
        EXPECT_NEAR(CsfJnd(field, grating, options), sampled, 1e-9) << cpd << " cpd, " << luminance << " cd/m2";
        EXPECT_NEAR(CsfJnd(field, half, options), 0.5 * sampled, 1e-9) << cpd << " cpd, " << luminance << " cd/m2";
      }
      EXPECT_NEAR(CsfJnd(field, Constant(cols, rows, 1.1 * luminance), options), 0.0, 1e-12);
    }
}

TEST(CsfJnd, BadValuesAreRefusedNamingTheField) {
  const Plane a = Constant(32, 32, 10);
  auto message = [&](const Plane& x, const Plane& y, CsfJndOptions o) {
    try {
      CsfJnd(x, y, o);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  CsfJndOptions o;
  o.minkowski_exponent = 0.5;
  EXPECT_NE(message(a, a, o).find("minkowski_exponent"), std::string::npos);
  o = {};
  o.pixel_deg = -1;
  EXPECT_NE(message(a, a, o).find("pixel_deg"), std::string::npos);
  EXPECT_NE(message(a, Constant(32, 31, 10), {}).find("differ in size"), std::string::npos);
  EXPECT_NE(message(Constant(32, 32, 0), a, {}).find("mean luminance is 0"), std::string::npos);
  EXPECT_NE(message(a, Constant(32, 32, -1), {}).find("negative"), std::string::npos);
}

}  // namespace
}  // namespace layerlab
