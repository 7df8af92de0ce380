// The eye's pupil function against closed forms and brute force written
// here: the Airy pattern (its peak pi D^2 / (4 lambda^2) per sr, which checks
// the PSF's normalization, and [2 J1(x) / x]^2), Hopkins' defocused OTF by a
// one-dimensional quadrature of the lens-shaped overlap, astigmatism on a
// square pupil as the product of two one-dimensional defocused patterns
// (Fresnel integrals by quadrature), coma by the Fraunhofer sum itself.
#include <cmath>
#include <complex>
#include <numbers>

#include "layerlab/eye/pupil_function.h"
#include "layerlab/framework/units.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

constexpr double kPi = std::numbers::pi;

PupilOptics Round(double diameter, double wavelength, double vergence = 0) {
  PupilOptics p;
  p.shape = PupilShape::kRound, p.diameter_m = diameter, p.wavelength_m = wavelength, p.vergence_diopters = vergence;
  return p;
}

// Hopkins' OTF of a round pupil of radius R defocused by V diopters at f
// cycles/rad along x: (1 / pi R^2) integral over the lens |u +- s / 2| <= R of
// cos(2 pi V f u_x), s = lambda f; the lens's height at u_x is
// 2 sqrt(R^2 - (|u_x| + s / 2)^2). Simpson's rule on 20000 intervals.
double HopkinsOtf(double diameter, double wavelength, double vergence, double f) {
  const double r = diameter / 2, s = wavelength * f, reach = r - s / 2;
  if (reach <= 0) return 0;
  const int n = 20000;
  double sum = 0;
  for (int k = 0; k <= n; ++k) {
    const double x = -reach + 2 * reach * k / n;
    const double h = 2 * std::sqrt(std::max(0.0, r * r - (std::abs(x) + s / 2) * (std::abs(x) + s / 2)));
    sum += (k == 0 || k == n ? 1 : k % 2 ? 4 : 2) * h * std::cos(2 * kPi * vergence * f * x);
  }
  return sum * (2 * reach / n) / 3 / (kPi * r * r);
}

TEST(PupilFunction, RoundPupilIsTheAiryPatternWithItsPhysicalPeak) {
  const PupilOptics p = Round(3e-3, 550e-9);
  const double spacing = PsfSpacingLimit(p) / 2;
  const PointSpread psf = PupilPointSpread(p, spacing, 129);
  const double peak = kPi * p.diameter_m * p.diameter_m / (4 * p.wavelength_m * p.wavelength_m);
  EXPECT_NEAR(psf.at(64, 64) / peak, 1.0, 2e-3);
  for (int k : {3, 7, 12, 20}) {
    const double x = kPi * p.diameter_m * k * spacing / p.wavelength_m;
    const double airy = std::pow(2 * std::cyl_bessel_j(1.0, x) / x, 2);
    EXPECT_NEAR(psf.at(64, 64 + k) / psf.at(64, 64), airy, 1e-3) << k;
    EXPECT_NEAR(psf.at(64 - k, 64) / psf.at(64, 64), airy, 1e-3) << k;
  }
  // Energy: the PSF over a field of 64 Airy radii holds 1 - J0^2 - J1^2 of the light
  // within them; over a square the tail beyond, 2 / (pi x), bounds what is missing.
  const PointSpread wide = PupilPointSpread(p, PsfSpacingLimit(p), 1024);
  double sum = 0;
  for (double v : wide.density) sum += v * wide.spacing_rad * wide.spacing_rad;
  const double x = kPi * p.diameter_m * 512 * wide.spacing_rad / p.wavelength_m;
  EXPECT_LT(sum, 1.0 + 1e-4);
  EXPECT_GT(sum, 1.0 - 2 / (kPi * x) - 1e-4);
}

TEST(PupilFunction, DefocusedOtfIsHopkins) {
  for (double d : {2e-3, 3e-3, 4e-3, 6e-3})
    for (double v : {0.0, 0.1, 0.25, 0.5, 1.0})
      for (double cpd : {5.0, 10.0, 30.0, 60.0}) {
        const double f = cpd / kRadiansPerDegree;
        const std::complex<double> otf = PupilOtf(Round(d, 555e-9, v), f, 0, 256);
        EXPECT_NEAR(otf.real(), HopkinsOtf(d, 555e-9, v, f), 2e-3) << d << " m, " << v << " D, " << cpd << " cpd";
        EXPECT_NEAR(otf.imag(), 0, 1e-9);
      }
  // The independent check's own figures: 30 cpd, 3 mm, 0.25 D is +0.196; 6 mm, 0.1 D is 0.262.
  EXPECT_NEAR(HopkinsOtf(3e-3, 555e-9, 0.25, 30 / kRadiansPerDegree), 0.196, 0.002);
  EXPECT_NEAR(HopkinsOtf(6e-3, 555e-9, 0.1, 30 / kRadiansPerDegree), 0.262, 0.002);
}

TEST(PupilFunction, TheLatticeOfOnePartIsTheOtf) {
  const PupilOptics p = Round(4e-3, 612e-9, 0.3);
  const int n = 128, q = 2 * n - 1;
  const OtfLattice lattice =
      PupilOtfLattice(p, n, 12, 1, std::vector<std::vector<MidpointShare>>(size_t(q) * q, {MidpointShare{}}));
  for (auto [mx, my] : {std::pair{0, 0}, {6, 0}, {0, -8}, {10, 4}}) {
    const double fx = mx * lattice.step_cycles_per_rad, fy = my * lattice.step_cycles_per_rad;
    EXPECT_NEAR(std::abs(lattice.value(0, mx, my) - PupilOtf(p, fx, fy, 512)), 0, 4e-3) << mx << ", " << my;
  }
  EXPECT_NEAR(lattice.value(0, 0, 0).real(), 1.0, 1e-12);
}

// |integral_{-L}^{L} exp(i (alpha x^2 + k a x)) dx|^2 / (lambda 2 L): a one-dimensional defocused pattern.
double DefocusedLine(double half, double alpha, double k, double a, double wavelength) {
  const int n = 8000;
  std::complex<double> sum = 0;
  for (int j = 0; j <= n; ++j) {
    const double x = -half + 2 * half * j / n;
    sum += double(j == 0 || j == n ? 1 : j % 2 ? 4 : 2) * std::polar(1.0, alpha * x * x + k * a * x);
  }
  return std::norm(sum * (2 * half / n) / 3.0) / (wavelength * 2 * half);
}

TEST(PupilFunction, AstigmatismOnASquarePupilIsTwoCrossedDefocusedLines) {
  PupilOptics p;
  p.shape = PupilShape::kSquare, p.diameter_m = 3e-3, p.wavelength_m = 550e-9;
  p.wavefront.pupil_diameter_m = 3e-3;
  p.wavefront.coefficients_m.assign(6, 0.0);
  p.wavefront.coefficients_m[5] = 0.15e-6;  // Z5 = sqrt(6) (x^2 - y^2) / R^2
  const double spacing = PsfSpacingLimit(p) / 2, k = 2 * kPi / p.wavelength_m, r = 1.5e-3;
  const double alpha = k * 0.15e-6 * std::sqrt(6.0) / (r * r);  // Phi = -W: exp(-i alpha x^2) exp(+i alpha y^2)
  const PointSpread psf = PupilPointSpread(p, spacing, 97);
  double peak = 0;
  for (double v : psf.density) peak = std::max(peak, v);
  for (auto [row, col] : {std::pair{48, 48}, {48, 60}, {40, 48}, {30, 70}, {55, 41}}) {
    const double ax = (col - 48) * spacing, ay = (48 - row) * spacing;
    const double expected =
        DefocusedLine(r, -alpha, k, ax, p.wavelength_m) * DefocusedLine(r, alpha, k, ay, p.wavelength_m);
    EXPECT_NEAR(psf.at(row, col) / peak, expected / peak, 2e-3) << row << ", " << col;
  }
}

TEST(PupilFunction, ComaIsTheFraunhoferSumAndMirrorsAboutItsAxis) {
  PupilOptics p = Round(4e-3, 555e-9);
  p.wavefront.pupil_diameter_m = 4e-3;
  p.wavefront.coefficients_m.assign(9, 0.0);
  p.wavefront.coefficients_m[8] = 0.2e-6;  // Z8: sqrt(8) (3 rho^3 - 2 rho) cos theta, coma along x
  const double spacing = PsfSpacingLimit(p) / 2;
  const PointSpread psf = PupilPointSpread(p, spacing, 81);
  // Mirror symmetric about the x axis; not about the y axis.
  double asymmetry = 0, largest = 0;
  for (double v : psf.density) largest = std::max(largest, v);
  for (int i = 0; i < 81; ++i)
    for (int j = 0; j < 81; ++j) {
      EXPECT_NEAR(psf.at(i, j), psf.at(80 - i, j), 1e-9 * largest);
      asymmetry = std::max(asymmetry, std::abs(psf.at(i, j) - psf.at(i, 80 - j)) / largest);
    }
  EXPECT_GT(asymmetry, 0.05);
  double peak = 0;
  for (double v : psf.density) peak = std::max(peak, v);
  // The Fraunhofer integral summed here over a 600 x 600 grid of the pupil.
  const int n = 600;
  const double h = p.diameter_m / n, k = 2 * kPi / p.wavelength_m;
  double energy = 0;
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b) energy += std::norm(PupilFunctionAt(p, -2e-3 + (b + 0.5) * h, -2e-3 + (a + 0.5) * h));
  for (auto [row, col] : {std::pair{40, 40}, {40, 46}, {40, 33}, {35, 44}}) {
    const double ax = (col - 40) * spacing, ay = (40 - row) * spacing;
    std::complex<double> sum = 0;
    for (int a = 0; a < n; ++a)
      for (int b = 0; b < n; ++b) {
        const double x = -2e-3 + (b + 0.5) * h, y = -2e-3 + (a + 0.5) * h;
        sum += PupilFunctionAt(p, x, y) * std::polar(1.0, k * (x * ax + y * ay));
      }
    const double density = std::norm(sum * h * h) / (p.wavelength_m * p.wavelength_m * energy * h * h);
    EXPECT_NEAR(psf.at(row, col) / peak, density / peak, 3e-3) << row << ", " << col;
  }
}

TEST(PupilFunction, SamplingRuleRefusesAnAliasedPsf) {
  const PupilOptics p = Round(4e-3, 555e-9);
  EXPECT_NO_THROW(PupilPointSpread(p, PsfSpacingLimit(p), 16));
  EXPECT_NE(testing::ErrorOf([&] { PupilPointSpread(p, 1.01 * PsfSpacingLimit(p), 16); }).find("would alias"),
            std::string::npos);
}

TEST(PupilFunction, StilesCrawfordApodizesTheAmplitude) {
  PupilOptics p = Round(6e-3, 555e-9);
  p.stiles_crawford_rho_per_mm2 = 0.05;
  // At r = 2 mm the intensity is 10^(-0.05 * 4) = 0.631, the amplitude its root.
  EXPECT_NEAR(std::abs(PupilFunctionAt(p, 2e-3, 0)), std::sqrt(std::pow(10.0, -0.2)), 1e-12);
  EXPECT_EQ(std::abs(PupilFunctionAt(p, 3.01e-3, 0)), 0.0);
}

}  // namespace
}  // namespace layerlab
