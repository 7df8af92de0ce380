// Diffraction at the pupil against the closed forms: the Airy pattern's
// first zero and profile (Bessel J1, computed here, not from the OTF the code
// multiplies by), the square pupil's sinc^2, and the MTF of a grating.
#include <cmath>
#include <functional>
#include <numbers>

#include "layerlab/analysis/fourier.h"
#include "layerlab/framework/units.h"
#include "layerlab/retina/diffraction.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

// The image of one bright sample at the center of a retina of n x n samples.
Image PointImage(const RetinaGrid& g) {
  Image image{g.cols, g.rows, {"R", "G", "B"}, std::vector<float>(size_t(g.cols) * g.rows * 3, 0.0f)};
  for (int c = 0; c < 3; ++c) image.pixels[(size_t(g.rows / 2) * g.cols + g.cols / 2) * 3 + c] = 1.0f;
  return image;
}

// The first local minimum along the central row, right of the center, refined by a parabola (rad).
double FirstZero(const Image& image, const RetinaGrid& g, int c) {
  const int i = g.rows / 2, j0 = g.cols / 2;
  for (int j = j0 + 1; j + 1 < g.cols; ++j) {
    double a = image.at(i, j - 1, c), b = image.at(i, j, c), d = image.at(i, j + 1, c);
    if (b <= a && b < d) return (j - j0 + 0.5 * (a - d) / (a - 2 * b + d)) * g.resolution_rad;
  }
  return NAN;
}

// The image of a point through `shape` of diameter d at three wavelengths:
// its first zero along the central row at zero_at x lambda / d (within
// `tolerance` samples), and its profile relative to the peak at `offsets`
// samples out against profile(x), x = pi d theta / lambda.
void CheckPointSpread(PupilShape shape, double d, const std::array<double, 3>& lambda, const RetinaGrid& g,
                      double zero_at, double tolerance, const std::function<double(double)>& profile,
                      const std::vector<int>& offsets) {
  Image image = PointImage(g);
  ApplyDiffraction(shape, d, lambda, g, &image);
  const int i = g.rows / 2, j0 = g.cols / 2;
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(FirstZero(image, g, c), zero_at * lambda[c] / d, tolerance * g.resolution_rad) << "channel " << c;
    for (int k : offsets) {
      const double x = std::numbers::pi * d * (k * g.resolution_rad) / lambda[c];
      EXPECT_NEAR(image.at(i, j0 + k, c) / image.at(i, j0, c), profile(x), 2e-3)
          << "channel " << c << ", " << k << " samples out";
    }
  }
}

TEST(Diffraction, RoundPupilIsTheAiryPatternWithItsFirstZeroAt1Point22LambdaOverD) {
  // j1's first zero 3.831706 / pi = 1.219670; the profile [2 J1(x) / x]^2.
  CheckPointSpread(PupilShape::kRound, 2e-3, {650e-9, 550e-9, 450e-9},
                   MakeRetinaGrid(0.3 * kRadiansPerDegree, 0.3 * kRadiansPerDegree, 0.0005 * kRadiansPerDegree),
                   1.219670, 0.02, [](double x) { return std::pow(2 * std::cyl_bessel_j(1.0, x) / x, 2); },
                   {5, 12, 20, 31});
}

TEST(Diffraction, SquarePupilIsSincSquaredWithZerosAtLambdaOverD) {
  // sinc^2's tails (1 / x^2) wrap around the padded image and lift its zeros a little: 0.05 samples.
  CheckPointSpread(PupilShape::kSquare, 3e-3, {612e-9, 549e-9, 465e-9},
                   MakeRetinaGrid(0.2 * kRadiansPerDegree, 0.2 * kRadiansPerDegree, 0.0004 * kRadiansPerDegree), 1.0,
                   0.05, [](double x) { return std::pow(std::sin(x) / x, 2); }, {7, 15});
}

TEST(Diffraction, GratingModulationIsTheDiffractionLimitedMtf) {
  // Round 3 mm pupil at 550 nm: cutoff D / lambda = 5454.5 cycles/rad = 95.20 cpd.
  // At 30 cpd nu = 0.31513 and MTF = (2/pi)(acos nu - nu sqrt(1 - nu^2)) = 0.60551.
  const double cpd = 30, nu = cpd / (3e-3 / 550e-9 * kRadiansPerDegree);
  const double mtf = 2 / std::numbers::pi * (std::acos(nu) - nu * std::sqrt(1 - nu * nu));
  EXPECT_NEAR(nu, 0.31513, 1e-5);
  EXPECT_NEAR(mtf, 0.60551, 1e-5);
  RetinaGrid g = MakeRetinaGrid(4 * kRadiansPerDegree, 0.05 * kRadiansPerDegree, 0.002 * kRadiansPerDegree);
  Image image{g.cols, g.rows, {"R", "G", "B"}, std::vector<float>(size_t(g.cols) * g.rows * 3)};
  for (int i = 0; i < g.rows; ++i)
    for (int j = 0; j < g.cols; ++j)
      for (int c = 0; c < 3; ++c)
        image.pixels[(size_t(i) * g.cols + j) * 3 + c] =
            float(0.5 + 0.5 * std::cos(2 * std::numbers::pi * cpd * g.angle_x(j) / kRadiansPerDegree));
  ApplyDiffraction(PupilShape::kRound, 3e-3, {550e-9, 550e-9, 550e-9}, g, &image);
  // The middle half of the row, a whole number of cycles.
  const int n = WholeCycleSamples(g.cols / 2, 0.002, cpd), start = (g.cols - n) / 2;
  std::vector<double> values, degrees;
  for (int j = start; j < start + n; ++j) {
    values.push_back(image.at(g.rows / 2, j, 1));
    degrees.push_back(g.angle_x(j) / kRadiansPerDegree);
  }
  EXPECT_NEAR(FourierAmplitude(values, degrees, cpd) / 0.5, mtf, 0.003);
  // The square pupil's at the same frequency: 1 - nu.
  ApplyDiffraction(PupilShape::kSquare, 3e-3, {550e-9, 550e-9, 550e-9}, g, &image);
  values.clear();
  for (int j = start; j < start + n; ++j) values.push_back(image.at(g.rows / 2, j, 1));
  EXPECT_NEAR(FourierAmplitude(values, degrees, cpd) / 0.5, mtf * (1 - nu), 0.003);
  EXPECT_THROW(ApplyDiffraction(PupilShape::kRound, 0, {550e-9, 550e-9, 550e-9}, g, &image), Error);
}

}  // namespace
}  // namespace layerlab
