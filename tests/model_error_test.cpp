// A wrong display model is detected, not fitted silently (issue 43): the noise
// of each board's corners measured without the model
// (calibration/detection_noise.h), the F test of the fit's residual against it
// (calibration/variance_ratio.h), and the fit that refuses a model error,
// scales its uncertainties by the measured noise and fits the focal length
// when parallax determines it.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "layerlab/calibration/calibration.h"
#include "layerlab/calibration/detection_noise.h"
#include "layerlab/calibration/variance_ratio.h"
#include "layerlab/tests/calibration_test_util.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

using testing::kArcmin;

// A 9 x 5 board of 25-pixel squares seen through a tilted, turned and
// distorted map (a projective map of the panel plane, then radial distortion
// of 3 % (third order) and 0.5 % (fifth order) at a field radius of 0.3 rad),
// each corner moved by Gaussian noise of sigma rad per axis.
std::vector<MarkerObservation> DistortedBoard(double sigma, std::mt19937_64* random) {
  std::normal_distribution<double> gauss(0.0, sigma);
  std::vector<MarkerObservation> board;
  const double k3 = 0.03 / (0.3 * 0.3), k5 = 0.005 / std::pow(0.3, 4);
  for (int b = 0; b < 5; ++b)
    for (int a = 0; a < 9; ++a) {
      MarkerObservation m;
      m.col = 60 + 25 * a + 0.5, m.row = 40 + 25 * b + 0.5;
      // The panel point (m, about its centre) seen from 0.25 m, the panel turned by 0.1 rad about y.
      const double x = (m.col - 180) * 2.5e-4, y = (m.row - 90) * 2.5e-4;
      const double depth = 0.25 + 0.1 * x;
      double tx = (x * std::cos(0.1)) / depth, ty = (y + 0.02 * x) / depth;
      const double r2 = tx * tx + ty * ty;
      const double scale = 1 + k3 * r2 + k5 * r2 * r2;
      m.angle_x = std::atan(tx * scale) + gauss(*random);
      m.angle_y = std::atan(ty * scale) + gauss(*random);
      board.push_back(m);
    }
  return board;
}

TEST(DetectionNoise, FindsTheNoiseAddedToADistortedBoard) {
  std::mt19937_64 random(43);
  const double sigma = 0.1 * kArcmin;
  double variance = 0;
  int dof = 0;
  for (int k = 0; k < 200; ++k) {
    const auto noise = EstimateBoardNoise(DistortedBoard(sigma, &random));
    ASSERT_TRUE(noise);
    EXPECT_EQ(noise->degrees_of_freedom, 2 * (45 - 10));
    variance += noise->degrees_of_freedom * noise->sigma_rad * noise->sigma_rad;
    dof += noise->degrees_of_freedom;
  }
  // 14000 degrees of freedom: the pooled estimate's own scatter is 0.6 %.
  const double pooled = std::sqrt(variance / dof);
  std::printf("pooled estimate %.5f arcmin for %.5f arcmin added\n", pooled / kArcmin, sigma / kArcmin);
  EXPECT_NEAR(pooled / sigma, 1.0, 0.03);
  // Without noise what is left is the map's own misfit, a small part of a good detector's noise.
  const auto clean = EstimateBoardNoise(DistortedBoard(0, &random));
  ASSERT_TRUE(clean);
  std::printf("noise-free board: %.5f arcmin\n", clean->sigma_rad / kArcmin);
  EXPECT_LT(clean->sigma_rad, 0.02 * kArcmin);
}

TEST(DetectionNoise, NeedsABoardThatSpansTwoDirections) {
  std::mt19937_64 random(1);
  std::vector<MarkerObservation> board = DistortedBoard(1e-5, &random);
  EXPECT_FALSE(EstimateBoardNoise({board.begin(), board.begin() + 15}));  // fewer than 16
  std::vector<MarkerObservation> three_rows(board.begin(), board.begin() + 27);
  EXPECT_FALSE(EstimateBoardNoise(three_rows));  // a cubic along the rows needs 4 of them
  EXPECT_TRUE(EstimateBoardNoise({board.begin(), board.begin() + 36}));
}

// The F density's upper tail beyond x, by Simpson's rule on t = ln x (brute force, apart from Fisher's z).
double FTail(int d1, int d2, double x) {
  auto log_density = [&](double v) {
    if (d2 == 0)  // chi-square over d1: v = chi2 / d1
      return std::log(d1) + (d1 / 2.0 - 1) * std::log(d1 * v) - d1 * v / 2 - (d1 / 2.0) * std::log(2.0) -
             std::lgamma(d1 / 2.0);
    return (d1 / 2.0) * std::log(static_cast<double>(d1) / d2) + (d1 / 2.0 - 1) * std::log(v) -
           ((d1 + d2) / 2.0) * std::log1p(static_cast<double>(d1) * v / d2) -
           (std::lgamma(d1 / 2.0) + std::lgamma(d2 / 2.0) - std::lgamma((d1 + d2) / 2.0));
  };
  const int n = 200000;
  const double a = std::log(x), b = std::log(x) + 6, h = (b - a) / n;
  double sum = 0;
  for (int i = 0; i <= n; ++i) {
    const double t = a + i * h, w = (i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2);
    sum += w * std::exp(log_density(std::exp(t)) + t);
  }
  return sum * h / 3;
}

TEST(VarianceRatio, CriticalValueLeavesTheStatedTail) {
  // The standard normal's 0.1 % point, as tables give it.
  EXPECT_NEAR(NormalUpperQuantile(1e-3), 3.090232306, 1e-8);
  EXPECT_NEAR(NormalUpperQuantile(0.5), 0.0, 1e-12);
  for (const auto& [d1, d2] : std::vector<std::pair<int, int>>{{60, 80}, {1070, 840}, {300, 0}, {2000, 0}}) {
    const double critical = CriticalVarianceRatio(d1, d2, 1e-3);
    const double tail = FTail(d1, d2, critical);
    std::printf("F(%d, %d): critical %.4f leaves %.5f above it\n", d1, d2, critical, tail);
    EXPECT_GT(tail, 0.9e-3) << d1 << ", " << d2;
    EXPECT_LT(tail, 1.1e-3) << d1 << ", " << d2;
  }
}

const DisplaySystem& Designed() {
  static const DisplaySystem system = Compile(LoadScene(testing::ExamplePath("paper_prototype.json")));
  return system;
}

// Markers of the paper prototype as built with its magnifier at `focal_length`,
// from 5 camera positions 2 mm apart, each photograph's noise recorded as
// `recorded` times the noise it has (exact, as a detector that knew it would).
Measurements WithDetectionNoise(double focal_length, double recorded, uint64_t seed = 1) {
  const std::vector<testing::PanelTruth> truth = testing::ExampleTruth();
  const DisplaySystem built = testing::BuiltSystem(Designed(), truth, {{"lens", 0.0, focal_length}});
  testing::SyntheticSetup setup = testing::ExampleSetup();
  setup.camera.intrinsics.reset();
  setup.camera.positions_m = {{0, 0}, {-2e-3, 0}, {2e-3, 0}, {0, -2e-3}, {0, 2e-3}};
  setup.noise.marker_sigma_rad = 0.2 * kArcmin;
  setup.noise.seed = seed;
  setup.luminance_codes.clear();
  Measurements m = testing::SyntheticMeasurements(built, truth, setup);
  for (Capture& c : m.captures)
    for (PanelMarkers& p : c.panels) p.detection_noise = DetectionNoise{recorded * setup.noise.marker_sigma_rad, 0};
  return m;
}

TEST(DetectionNoiseFormat, RoundTripsAndBadValuesAreRefusedByPointer) {
  Measurements m = WithDetectionNoise(75e-3, 1.0);
  m.captures[0].panels[1].detection_noise = DetectionNoise{0.123456 * kArcmin, 70};
  const nlohmann::json written = nlohmann::json::parse(FormatMeasurements(m));
  EXPECT_EQ(written["captures"][0]["detection_noise"][m.captures[0].panels[1].panel]["sigma"], "0.1235 arcmin");
  const Measurements back = ParseMeasurements(written, "m.json");
  const std::string named = m.captures[0].panels[1].panel;
  std::optional<DetectionNoise> noise;
  for (const PanelMarkers& p : back.captures[0].panels)
    if (p.panel == named) noise = p.detection_noise;
  ASSERT_TRUE(noise);
  EXPECT_NEAR(noise->sigma_rad, 0.1235 * kArcmin, 1e-12);
  EXPECT_EQ(noise->degrees_of_freedom, 70);
  for (const PanelMarkers& p : back.captures[0].panels) {
    if (p.panel != named) {
      EXPECT_EQ(p.detection_noise->degrees_of_freedom, 0) << "written without them: exact";
    }
  }
  auto refused = [&](nlohmann::json doc, const std::string& where) {
    try {
      ParseMeasurements(doc, "m.json");
      ADD_FAILURE() << doc["captures"][0]["detection_noise"].dump() << " read";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("m.json: " + where), std::string::npos) << e.what();
    }
  };
  nlohmann::json bad = written;
  bad["captures"][0]["detection_noise"]["rear_a"]["sigma"] = "-0.1 arcmin";
  refused(bad, "/captures/0/detection_noise/rear_a/sigma");
  bad = written;
  bad["captures"][0]["detection_noise"]["rear_a"]["degrees_of_freedom"] = 0;
  refused(bad, "/captures/0/detection_noise/rear_a/degrees_of_freedom");
  bad = written;
  bad["captures"][0]["detection_noise"]["rear_c"] = {{"sigma", "0.1 arcmin"}};
  refused(bad, "/captures/0/detection_noise/rear_c");
}

CalibrationOptions FocalLength(FitChoice choice) {
  CalibrationOptions o;
  o.focal_length = choice;
  o.lens_gaps = FitChoice::kHold;
  return o;
}

TEST(ModelError, AFocalLengthHeldTwoPercentOffIsRefusedNamingTheModelError) {
  const Measurements m = WithDetectionNoise(76.5e-3, 1.0);
  CalibratedDisplay display;
  const CalibrationReport held = Calibrate(Designed(), m, FocalLength(FitChoice::kHold), &display);
  std::printf("held: %s\n", held.message.substr(0, 120).c_str());
  EXPECT_FALSE(held.IsSolutionUsable());
  EXPECT_NE(held.message.find("model error: the markers' residual is"), std::string::npos) << held.message;
  EXPECT_NE(held.message.find("It is largest in panel \""), std::string::npos) << held.message;
  EXPECT_GT(held.variance_ratio, held.critical_variance_ratio);
  EXPECT_FALSE(held.parameters.empty()) << "the wrong model's parameters are still reported";

  CalibrationOptions accept = FocalLength(FitChoice::kHold);
  accept.accept_model_error = true;
  const CalibrationReport accepted = Calibrate(Designed(), m, accept, &display);
  EXPECT_TRUE(accepted.IsSolutionUsable()) << accepted.message;
  ASSERT_FALSE(accepted.warnings.empty());
  EXPECT_NE(accepted.FullReport().find("warning: model error:"), std::string::npos);

  // By default the focal length is fitted (five camera positions see parallax): recovered, no model error.
  const CalibrationReport fitted = Calibrate(Designed(), m, CalibrationOptions{}, &display);
  ASSERT_TRUE(fitted.IsSolutionUsable()) << fitted.message;
  EXPECT_TRUE(fitted.model_error.empty());
  const ParameterEstimate* f = fitted.find("lens", "focal_length");
  ASSERT_TRUE(f && f->std_dev);
  EXPECT_EQ(f->status, ParameterStatus::kFitted);
  std::printf("fitted: focal length %.4f +- %.4f mm\n", 1e3 * f->value, 1e3 * *f->std_dev);
  EXPECT_LT(std::abs(f->value - 76.5e-3), 3 * *f->std_dev) << fitted.FullReport();
}

TEST(ModelError, ARightModelPassesTheTest) {
  for (uint64_t seed = 1; seed <= 5; ++seed) {
    CalibratedDisplay display;
    const CalibrationReport r =
        Calibrate(Designed(), WithDetectionNoise(75e-3, 1.0, seed), CalibrationOptions{}, &display);
    EXPECT_TRUE(r.IsSolutionUsable()) << r.message;
    EXPECT_TRUE(r.noise_from_detection);
    EXPECT_NEAR(r.variance_ratio, 1.0, 0.15) << seed;
  }
}

// The uncertainties scale with the noise measured in the photographs, not the residual's: a noise recorded
// twice as large doubles them; one recorded at half the truth is a model error (the residual is twice it).
TEST(ModelError, UncertaintiesFollowTheDetectionNoise) {
  CalibratedDisplay display;
  const CalibrationReport unit = Calibrate(Designed(), WithDetectionNoise(75e-3, 1.0), CalibrationOptions{}, &display);
  const CalibrationReport twice = Calibrate(Designed(), WithDetectionNoise(75e-3, 2.0), CalibrationOptions{}, &display);
  ASSERT_TRUE(unit.IsSolutionUsable() && twice.IsSolutionUsable());
  for (const char* quantity : {"distance", "offset_x", "rotation"}) {
    const ParameterEstimate *a = unit.find("rear_b", quantity), *b = twice.find("rear_b", quantity);
    ASSERT_TRUE(a && b && a->std_dev && b->std_dev);
    EXPECT_NEAR(*b->std_dev / *a->std_dev, 2.0, 0.02) << quantity;
  }
  const CalibrationReport half = Calibrate(Designed(), WithDetectionNoise(75e-3, 0.5), CalibrationOptions{}, &display);
  EXPECT_FALSE(half.IsSolutionUsable());
  EXPECT_NEAR(half.variance_ratio, 4.0, 0.6);
}

}  // namespace
}  // namespace layerlab
