// The eye's temporal contrast sensitivity (eye/temporal_csf.h) against the
// psychophysics of flicker: the critical flicker frequency rises linearly
// with log luminance (the Ferry-Porter law; about 10 Hz a decade in the
// fovea, Tyler and Hamer 1990) and with log area (the Granit-Harper law), is
// 40 to 60 Hz for a small foveal field at office luminance, passes 60 Hz for
// a large bright field (60 Hz flicker of a large bright display is visible)
// and stays below the 90 to 100 Hz where it saturates (Fernandez-Alonso, Innes
// and Read 2023); a flicker at its CFF is at threshold; bad values are
// refused naming them.
#include <array>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>
#include "layerlab/eye/temporal_csf.h"
#include "layerlab/framework/error.h"

namespace layerlab {
namespace {

// The least-squares line through (x, y): {slope, largest residual}.
std::array<double, 2> Line(const std::vector<double>& x, const std::vector<double>& y) {
  const double n = x.size();
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (size_t i = 0; i < x.size(); ++i) sx += x[i], sy += y[i], sxx += x[i] * x[i], sxy += x[i] * y[i];
  const double slope = (n * sxy - sx * sy) / (n * sxx - sx * sx), intercept = (sy - slope * sx) / n;
  double worst = 0;
  for (size_t i = 0; i < x.size(); ++i) worst = std::max(worst, std::abs(y[i] - intercept - slope * x[i]));
  return {slope, worst};
}

TEST(TemporalCsf, TheCffRisesLinearlyWithLogLuminanceFerryPorter) {
  std::vector<double> log_l, cff;
  for (double l = 1; l <= 1000; l *= std::sqrt(10.0)) {
    log_l.push_back(std::log10(l));
    cff.push_back(CriticalFlickerFrequency({l, 4, 0}));
  }
  const auto [slope, residual] = Line(log_l, cff);
  EXPECT_GT(slope, 7) << "Hz per decade";
  EXPECT_LT(slope, 15) << "Hz per decade";
  EXPECT_LT(residual, 1.5) << "Hz off the line";
}

TEST(TemporalCsf, TheCffRisesLinearlyWithLogAreaGranitHarper) {
  std::vector<double> log_a, cff;
  for (double a = 1; a <= 1000; a *= std::sqrt(10.0)) {
    log_a.push_back(std::log10(a));
    cff.push_back(CriticalFlickerFrequency({100, a, 0}));
  }
  for (size_t i = 1; i < cff.size(); ++i) EXPECT_GT(cff[i], cff[i - 1]);
  const auto [slope, residual] = Line(log_a, cff);
  EXPECT_GT(slope, 4) << "Hz per decade of area";
  EXPECT_LT(residual, 3) << "Hz off the line";
}

TEST(TemporalCsf, TheCffHasThePsychophysicsMagnitudes) {
  const double foveal = CriticalFlickerFrequency({100, 4, 0});  // a 2.3 deg disc at 100 cd/m2
  EXPECT_GT(foveal, 40);
  EXPECT_LT(foveal, 60);
  const double large = CriticalFlickerFrequency({200, 30 * 30, 0});  // a 30 deg field at 200 cd/m2
  EXPECT_GT(large, 60);
  EXPECT_LT(large, 100);
  EXPECT_LT(CriticalFlickerFrequency({380, 100, 20}), 100);  // peripheral, bright: below the saturation
}

TEST(TemporalCsf, AFlickerAtItsCffIsAtThreshold) {
  for (double m : {0.1, 0.5, 1.0, 2.0}) {
    const FlickerConditions c{50, 25, 5};
    const double cff = CriticalFlickerFrequency(c, m);
    ASSERT_GT(cff, 0) << m;
    EXPECT_NEAR(m * TemporalContrastSensitivity(cff, c), 1, 0.01) << m;
    EXPECT_LT(m * TemporalContrastSensitivity(cff + 1, c), 1) << m;  // faster: below threshold
  }
  EXPECT_LT(CriticalFlickerFrequency({50, 25, 5}, 0.1), CriticalFlickerFrequency({50, 25, 5}, 1));
  EXPECT_EQ(CriticalFlickerFrequency({50, 25, 5}, 1e-6), 0);  // visible at no frequency
}

// The formula as eye/temporal_csf.h states it, step by step here, at one condition (200 cd/m2 on a 100 deg2
// disc 5 deg out, 30 Hz): its pupil from log10 (3.76 mm; the natural log would give 2.70 mm), the two temporal
// filters, the noises and extents.
TEST(TemporalCsf, TheDiscsSensitivityIsTheStatedFormula) {
  const double pi = std::acos(-1.0), L = 200, A = 100, e = 5, w = 30;
  const double X0 = std::sqrt(A), sigma = std::sqrt(A / pi), u = 3 / (std::sqrt(pi) * 2 * sigma);  // sigma >= 2.5
  const double d = 5 - 3 * std::tanh(0.4 * std::log10(L * A / 1600));
  EXPECT_NEAR(d, 3.76214, 1e-5);
  const double E = pi * d * d / 4 * L * (1 - std::pow(d / 9.7, 2) + std::pow(d / 12.4, 4));
  auto ganglion = [&](double fraction) {
    return 33163.2 * fraction * (0.9851 * std::pow(1 + e / 1.058, -2) + 0.0149 * std::exp(-e / 22.14));
  };
  const double rf = 33163.2 / 2 / ganglion(0.5), D = std::sqrt(4 / pi * A);
  const double tau1 = 0.0334009 / (1 + 0.55 * std::log(1 + std::pow(1 + D, 0.6) * E / 1.32776 * rf));
  const double tau2 = 0.0477005 / (1 + 0.37 * std::log(1 + std::pow(1 + D / 3.2, 5) * E / 120));
  const double h1 = std::pow(1 + std::pow(2 * pi * w * tau1, 2), -3.5),
               h2 = std::pow(1 + std::pow(2 * pi * w * tau2, 2), -2);
  const double lateral = h1 * (1 - h2 * (1 - std::sqrt(1 - std::exp(-std::pow(u / 2.44734, 2)))));
  const double eta = 0.03 * (0.4 / (1 + std::pow(e / 7, 2)) + 0.48 / (1 + std::pow(e / 20, 2)) + 0.12);
  const double x_max = 12 / std::sqrt(0.85 / (1 + std::pow(e / 4, 2)) + 0.15 / (1 + std::pow(e / 12, 2)));
  const double half = X0 / 2;
  const double X =
      1 / std::sqrt(1 / A + 1 / (x_max * x_max) + ((half * half + 4 * e * e) / (half * half) + e * e) * u * u / 225);
  const double Y = 1 / std::sqrt(1 / A + 1 / (x_max * x_max) + (1 + e * e) * u * u / 225);
  const double noise = 1 / (eta * 1.240e6 * E) + 3e-8 * (1 + 0.171344 * e) / (lateral * lateral);
  const double S = std::sqrt(2.0) / (2 * 8.36831) * std::sqrt(X * Y * 0.1 / noise);
  EXPECT_NEAR(TemporalContrastSensitivity(w, {L, A, e}), S, 1e-12 * S);
}

TEST(TemporalCsf, BadValuesAreRefusedNamingThem) {
  const std::vector<std::pair<FlickerConditions, std::string>> bad = {
      {{-1, 4, 0}, "luminance"}, {{100, 0, 0}, "area"}, {{100, 4, -2}, "eccentricity"}, {{NAN, 4, 0}, "luminance"}};
  for (const auto& [c, name] : bad) {
    try {
      TemporalContrastSensitivity(10, c);
      FAIL() << name << " accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(TemporalContrastSensitivity(-1, {}), Error);
  EXPECT_THROW(CriticalFlickerFrequency({}, 0), Error);
}

}  // namespace
}  // namespace layerlab
