// Calibration fits on synthetic measurements of the paper prototype built
// with known placements (tests/calibration_test_util.h): parameters recovered
// within tolerances derived from the noise and the marker layout, outliers
// handled by the robust loss, degenerate data reported, not silently fitted.
#include <cmath>
#include <cstdlib>
#include <numbers>

#include "layerlab/calibration/calibrated_scene.h"
#include "layerlab/calibration/calibration.h"
#include "layerlab/calibration/fit_steps.h"
#include "layerlab/calibration/scalar_fit.h"
#include "layerlab/framework/json_file.h"
#include "layerlab/tests/calibration_test_util.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

using testing::BuiltSystem;
using testing::ExampleSetup;
using testing::ExampleTruth;
using testing::PanelTruth;
using testing::SyntheticSetup;

using testing::kArcmin;
using testing::kSigmas;

const DisplaySystem& Designed() {
  static const DisplaySystem system = Compile(LoadScene(testing::ExamplePath("paper_prototype.json")));
  return system;
}

bool HasWarning(const CalibrationReport& report, const std::string& part) {
  for (const std::string& w : report.warnings)
    if (w.find(part) != std::string::npos) return true;
  return false;
}

// The synthetic captures list every layer, in order.
int LayerIndexIn(const DisplaySystem& system, const std::string& name) {
  for (size_t k = 0; k < system.layers.size(); ++k)
    if (system.layers[k].name == name) return static_cast<int>(k);
  return -1;
}

// Geometry only: angles, one camera position unless told.
SyntheticSetup GeometrySetup(double sigma_arcmin) {
  SyntheticSetup setup = ExampleSetup();
  setup.camera.intrinsics.reset();
  setup.camera.positions_m = {{0.0, 0.0}};
  setup.noise.marker_sigma_rad = sigma_arcmin * kArcmin;
  setup.luminance_codes.clear();
  return setup;
}

// The largest error of any panel's distance, offset or rotation, in units of
// its expected standard deviation; also checks the reported ones against those.
double WorstGeometryError(const DisplaySystem& built, const Measurements& m, const CalibrationReport& report,
                          const CalibratedDisplay& display, double sigma, bool check_std_dev = true) {
  double worst = 0;
  for (const VirtualLayer& layer : built.layers) {
    const PanelMarkers& markers = m.captures.front().panels[LayerIndexIn(built, layer.name)];
    testing::GeometrySigma expected =
        testing::ExpectedGeometrySigma(layer, markers, static_cast<int>(m.captures.size()), sigma);
    const CalibratedPanel* p = display.find(layer.name);
    EXPECT_NE(p, nullptr);
    if (!p) return INFINITY;
    const double errors[] = {std::abs(p->distance_m - layer.panel_distance_m) / expected.distance,
                             std::abs(p->eye_from_panel_x_m - layer.panel.eye_from_panel_m[0]) / expected.offset,
                             std::abs(p->eye_from_panel_y_m - layer.panel.eye_from_panel_m[1]) / expected.offset,
                             std::abs(p->rotation_rad - layer.panel.rotation_rad) / expected.rotation};
    for (double e : errors) worst = std::max(worst, e);
    if (!check_std_dev) continue;
    // The reported uncertainties (ceres::Covariance, scaled by the residuals' noise) agree with these.
    const std::pair<const char*, double> quantities[] = {{"distance", expected.distance},
                                                         {"offset_x", expected.offset},
                                                         {"offset_y", expected.offset},
                                                         {"rotation", expected.rotation}};
    for (const auto& [quantity, sd] : quantities) {
      const ParameterEstimate* estimate = report.find(layer.name, quantity);
      EXPECT_NE(estimate, nullptr) << layer.name << " " << quantity;
      if (!estimate) continue;
      EXPECT_EQ(estimate->status, ParameterStatus::kFitted);
      EXPECT_TRUE(estimate->std_dev.has_value());
      if (estimate->std_dev) {
        EXPECT_TRUE(*estimate->std_dev > 0.5 * sd && *estimate->std_dev < 1.5 * sd)
            << layer.name << " " << quantity << ": reported " << *estimate->std_dev << ", expected about " << sd;
      }
    }
  }
  return worst;
}

TEST(CalibrationTest, RecoversPlacementsWithinTheNoise) {
  const std::vector<PanelTruth> truth = ExampleTruth();
  const DisplaySystem built = BuiltSystem(Designed(), truth);
  const SyntheticSetup setup = GeometrySetup(0.3);
  const Measurements m = testing::SyntheticMeasurements(built, truth, setup);
  CalibratedDisplay display;
  const CalibrationReport report = Calibrate(Designed(), m, CalibrationOptions{}, &display);
  ASSERT_TRUE(report.IsSolutionUsable()) << report.message;
  EXPECT_TRUE(report.warnings.empty()) << report.FullReport();
  EXPECT_LT(WorstGeometryError(built, m, report, display, setup.noise.marker_sigma_rad), kSigmas)
      << report.FullReport();
  // The designed placement is off by arcminutes; the fit leaves only the noise
  // (per marker the RMS over two axes: sqrt(2) sigma).
  EXPECT_GT(report.marker_rms_before_rad, 20 * setup.noise.marker_sigma_rad);
  EXPECT_TRUE(testing::Close(report.marker_rms_after_rad, std::sqrt(2.0) * setup.noise.marker_sigma_rad, 0.15));
  EXPECT_TRUE(testing::Close(report.marker_noise_rad, setup.noise.marker_sigma_rad, 0.15));
}

TEST(CalibrationTest, WithoutNoiseRecoversPlacementsExactly) {
  const std::vector<PanelTruth> truth = ExampleTruth();
  const DisplaySystem built = BuiltSystem(Designed(), truth);
  const Measurements m = testing::SyntheticMeasurements(built, truth, GeometrySetup(0.0));
  CalibratedDisplay display;
  const CalibrationReport report = Calibrate(Designed(), m, CalibrationOptions{}, &display);
  ASSERT_TRUE(report.IsSolutionUsable()) << report.message;
  testing::ExpectPlacementsOf(built, display, 1e-9);
  EXPECT_LT(report.marker_rms_after_rad, 1e-10);
}

TEST(CalibrationTest, FitsTheFocalLengthFromParallax) {
  std::vector<PanelTruth> truth = ExampleTruth();
  // The lens is not quite as specified; the panels stand at their distances from it.
  const DisplaySystem built = BuiltSystem(Designed(), truth, {{"lens", 0.0, 75.4e-3}});
  SyntheticSetup setup = GeometrySetup(0.3);
  setup.camera.positions_m = {{-2e-3, 0.0}, {2e-3, 0.0}, {0.0, -2e-3}, {0.0, 2e-3}};
  const Measurements m = testing::SyntheticMeasurements(built, truth, setup);
  CalibrationOptions options;
  options.focal_length = FitChoice::kFit;
  CalibratedDisplay display;
  const CalibrationReport report = Calibrate(Designed(), m, options, &display);
  ASSERT_TRUE(report.IsSolutionUsable()) << report.message;
  const ParameterEstimate* f = report.find("lens", "focal_length");
  ASSERT_NE(f, nullptr);
  ASSERT_EQ(f->status, ParameterStatus::kFitted);
  ASSERT_TRUE(f->std_dev.has_value());
  EXPECT_LT(*f->std_dev, 0.1e-3) << "parallax of 4 mm should fix the focal length to a tenth of a millimeter";
  EXPECT_LT(std::abs(f->value - 75.4e-3), kSigmas * *f->std_dev) << report.FullReport();
  EXPECT_TRUE(testing::Close(report.marker_rms_after_rad, std::sqrt(2.0) * setup.noise.marker_sigma_rad, 0.15));

  // Held at its scene value, the same data cannot be fitted down to the noise.
  CalibratedDisplay held;
  CalibrationOptions hold;
  hold.focal_length = FitChoice::kHold;
  hold.lens_gaps = FitChoice::kHold;
  const CalibrationReport fixed = Calibrate(Designed(), m, hold, &held);
  ASSERT_TRUE(fixed.IsSolutionUsable());
  EXPECT_GT(fixed.marker_rms_after_rad, 1.4 * report.marker_rms_after_rad);
}

TEST(CalibrationTest, FocalLengthWithoutParallaxIsUndetermined) {
  const std::vector<PanelTruth> truth = ExampleTruth();
  const DisplaySystem built = BuiltSystem(Designed(), truth);
  const Measurements m = testing::SyntheticMeasurements(built, truth, GeometrySetup(0.3));
  CalibrationOptions options;
  options.focal_length = FitChoice::kFit;
  CalibratedDisplay display;
  const CalibrationReport report = Calibrate(Designed(), m, options, &display);
  ASSERT_TRUE(report.IsSolutionUsable()) << report.message;
  const ParameterEstimate* f = report.find("lens", "focal_length");
  ASSERT_NE(f, nullptr);
  EXPECT_EQ(f->status, ParameterStatus::kUndetermined);
  EXPECT_FALSE(f->std_dev.has_value());
  EXPECT_EQ(f->value, Designed().focal_length_m);
  EXPECT_TRUE(HasWarning(report,
                         "the focal length cannot be told from the panel distances while each panel is seen "
                         "from one camera position only"))
      << report.FullReport();
}

TEST(CalibrationTest, RobustLossDiscountsOutliersThatBiasLeastSquares) {
  const std::vector<PanelTruth> truth = ExampleTruth();
  const DisplaySystem built = BuiltSystem(Designed(), truth);
  SyntheticSetup setup = GeometrySetup(0.3);
  setup.noise.outlier_fraction = 0.1;
  setup.noise.outlier_size_rad = 30 * kArcmin;
  const Measurements m = testing::SyntheticMeasurements(built, truth, setup);
  const double sigma = setup.noise.marker_sigma_rad;

  CalibratedDisplay plain_display;
  const CalibrationReport plain = Calibrate(Designed(), m, CalibrationOptions{}, &plain_display);
  ASSERT_TRUE(plain.IsSolutionUsable()) << plain.message;
  EXPECT_GT(WorstGeometryError(built, m, plain, plain_display, sigma, false), 3 * kSigmas) << plain.FullReport();
  EXPECT_TRUE(HasWarning(plain, "beyond 6 sigma of the noise")) << plain.FullReport();
  EXPECT_TRUE(HasWarning(plain, "--loss cauchy discounts them")) << plain.FullReport();
  int outliers = 0;  // 30 arcmin against a loss scale of 1 arcmin and 0.3 arcmin of noise: every one beyond it
  for (const Capture& c : m.captures)
    for (const PanelMarkers& p : c.panels)
      for (const MarkerObservation& o : p.markers) {
        const auto truth_angle =
            ImagedMarker(built, built.layers[LayerIndexIn(built, p.panel)], o.col, o.row, {}, c.camera_position);
        outliers += std::hypot(o.angle_x - truth_angle[0], o.angle_y - truth_angle[1]) > 10 * kArcmin;
      }
  ASSERT_GT(outliers, 0);

  for (RobustLoss loss : {RobustLoss::kCauchy, RobustLoss::kHuber}) {
    CalibrationOptions options;
    options.loss = loss;
    CalibratedDisplay display;
    const CalibrationReport robust = Calibrate(Designed(), m, options, &display);
    ASSERT_TRUE(robust.IsSolutionUsable()) << robust.message;
    // A tenth of the markers is lost to the outliers.
    EXPECT_LT(WorstGeometryError(built, m, robust, display, sigma / std::sqrt(0.9), false), kSigmas)
        << ToString(loss) << "\n"
        << robust.FullReport();
    EXPECT_TRUE(testing::Close(robust.marker_noise_rad, sigma, 0.25)) << ToString(loss);
    // It says how many it weighted down (the outliers, give or take a marker near the scale) and where.
    const std::string counted = "the " + ToString(loss) + " loss weighted " + std::to_string(outliers) + " of " +
                                std::to_string(m.marker_count()) + " markers by less than half";
    EXPECT_TRUE(HasWarning(robust, counted)) << counted << "\n" << robust.FullReport();
    EXPECT_TRUE(HasWarning(robust, " of panel \"")) << robust.FullReport();
  }
}

TEST(CalibrationTest, OneMarkerPerPanelLeavesDistanceAndRotationUndetermined) {
  const std::vector<PanelTruth> truth = ExampleTruth();
  const DisplaySystem built = BuiltSystem(Designed(), truth);
  SyntheticSetup setup = GeometrySetup(0.3);
  setup.grid = {1, 1, 0.1};
  const Measurements m = testing::SyntheticMeasurements(built, truth, setup);
  CalibratedDisplay display;
  const CalibrationReport report = Calibrate(Designed(), m, CalibrationOptions{}, &display);
  ASSERT_TRUE(report.IsSolutionUsable()) << report.message;
  for (const VirtualLayer& layer : Designed().layers) {
    for (const char* quantity : {"distance", "rotation"}) {
      const ParameterEstimate* p = report.find(layer.name, quantity);
      ASSERT_NE(p, nullptr);
      EXPECT_EQ(p->status, ParameterStatus::kUndetermined) << layer.name << " " << quantity;
      EXPECT_EQ(p->value, p->scene_value) << layer.name << " " << quantity;
      EXPECT_FALSE(p->std_dev.has_value());
    }
    EXPECT_EQ(report.find(layer.name, "offset_x")->status, ParameterStatus::kFitted);
  }
  EXPECT_TRUE(HasWarning(report,
                         "panel \"rear_a\": its markers show a single panel pixel (640.0, 400.0), which fixes "
                         "the offset but not the rotation nor the magnification: its distance and rotation "
                         "keep their scene values (72.8070 mm, 0.0000 deg)"))
      << report.FullReport();
  // Two residuals per panel for its two offsets: nothing is left to estimate the noise from.
  EXPECT_TRUE(HasWarning(report, "no uncertainties for the geometry: no redundancy")) << report.FullReport();
}

TEST(CalibrationTest, CollinearMarkersAreReported) {
  const std::vector<PanelTruth> truth = ExampleTruth();
  const DisplaySystem built = BuiltSystem(Designed(), truth);
  SyntheticSetup setup = GeometrySetup(0.3);
  setup.grid = {7, 1, 0.1};  // one row across each panel
  const Measurements m = testing::SyntheticMeasurements(built, truth, setup);
  CalibratedDisplay display;
  const CalibrationReport report = Calibrate(Designed(), m, CalibrationOptions{}, &display);
  ASSERT_TRUE(report.IsSolutionUsable()) << report.message;
  for (const VirtualLayer& layer : Designed().layers)
    EXPECT_TRUE(HasWarning(report, "panel \"" + layer.name + "\": its markers lie on one line of the panel"))
        << report.FullReport();
  // A row still fixes a similarity (its length, direction and place): the
  // placement is fitted, within the noise.
  EXPECT_LT(WorstGeometryError(built, m, report, display, setup.noise.marker_sigma_rad, false), kSigmas);
}

// A panel built mirrored (its "reversed" wrong in the scene): its markers
// fit the mirror image far better, and the report says so for that panel only.
TEST(CalibrationTest, MirroredPanelIsReported) {
  const std::vector<PanelTruth> truth = ExampleTruth();
  DisplaySystem built = BuiltSystem(Designed(), truth);
  built.layers[1].flip_x = !built.layers[1].flip_x;
  const Measurements m = testing::SyntheticMeasurements(built, truth, GeometrySetup(0.3));
  CalibratedDisplay display;
  const CalibrationReport report = Calibrate(Designed(), m, CalibrationOptions{}, &display);
  for (size_t k = 0; k < Designed().layers.size(); ++k)
    EXPECT_EQ(HasWarning(report, "panel \"" + Designed().layers[k].name + "\": its markers fit a mirror image"), k == 1)
        << Designed().layers[k].name << "\n"
        << report.FullReport();
}

TEST(CalibrationTest, FarthestPanelReferenceCentersItAndFitsTheCamera) {
  // The farthest panel defines the axis: built centered and level, seen by a turned camera.
  std::vector<PanelTruth> truth = ExampleTruth();
  truth[0].eye_from_panel_x_m = truth[0].eye_from_panel_y_m = truth[0].rotation = 0;
  const DisplaySystem built = BuiltSystem(Designed(), truth);
  SyntheticSetup setup = GeometrySetup(0.0);
  setup.camera.pan_rad = 10 * kArcmin, setup.camera.tilt_rad = -5 * kArcmin,
  setup.camera.roll_rad = 0.3 * std::numbers::pi / 180;
  const Measurements m = testing::SyntheticMeasurements(built, truth, setup);
  CalibrationOptions options;
  options.reference = AxisReference::kFarthestPanel;
  CalibratedDisplay display;
  const CalibrationReport report = Calibrate(Designed(), m, options, &display);
  ASSERT_TRUE(report.IsSolutionUsable()) << report.message;
  const CalibratedPanel* farthest = display.find("rear_a");
  EXPECT_EQ(farthest->eye_from_panel_x_m, 0.0);
  EXPECT_EQ(farthest->rotation_rad, 0.0);
  EXPECT_EQ(report.find("rear_a", "offset_x")->status, ParameterStatus::kReference);
  testing::ExpectPlacementsOf(built, display, 1e-9);
  EXPECT_NEAR(report.find("camera", "pan")->value, setup.camera.pan_rad, 1e-9);
  EXPECT_NEAR(report.find("camera", "tilt")->value, setup.camera.tilt_rad, 1e-9);
  EXPECT_NEAR(report.find("camera", "roll")->value, setup.camera.roll_rad, 1e-9);
  EXPECT_LT(report.marker_rms_after_rad, 1e-10);
}

TEST(CalibrationTest, RecoversGammaFromNoisyLuminance) {
  const std::vector<int> codes = ExampleSetup().luminance_codes;
  const double sigma = 0.005;  // of the maximum
  SyntheticNoise noise;
  noise.luminance_sigma = sigma;
  noise.seed = 7;
  Measurements m;
  m.file = "synthetic";
  m.luminance.push_back(SyntheticLuminance("rear_a", codes, 120.0, 0.004, 2.4, noise));
  CalibratedDisplay display;
  const CalibrationReport report = Calibrate(Designed(), m, CalibrationOptions{}, &display);
  ASSERT_TRUE(report.IsSolutionUsable()) << report.message;
  const double expected = testing::ExpectedLuminanceSigma(codes, 120.0, 0.004, 2.4, sigma).gamma;
  ASSERT_LT(expected, 0.05);  // the data are good enough for the test to mean something
  const ParameterEstimate* gamma = report.find("rear_a", "gamma");
  ASSERT_NE(gamma, nullptr);
  EXPECT_EQ(gamma->status, ParameterStatus::kFitted);
  EXPECT_EQ(gamma->scene_value, 2.4);
  EXPECT_LT(std::abs(display.find("rear_a")->gamma - 2.4), kSigmas * expected) << report.FullReport();
  ASSERT_TRUE(gamma->std_dev.has_value());
  EXPECT_TRUE(*gamma->std_dev > 0.5 * expected && *gamma->std_dev < 1.5 * expected)
      << *gamma->std_dev << " vs " << expected;
  EXPECT_NEAR(display.find("rear_a")->max_luminance, 120.0, 120.0 * kSigmas * sigma);
  // Panels without markers keep their geometry; without luminance, their curve.
  EXPECT_FALSE(display.find("rear_a")->geometry_measured);
  EXPECT_FALSE(display.find("rear_b")->luminance_measured);
}

TEST(CalibrationTest, RecoversGammaFromADifferentStart) {
  // The scene says 2.4; the panel really has 1.8: the fit must travel.
  const std::vector<int> codes = ExampleSetup().luminance_codes;
  SyntheticNoise noise;
  noise.luminance_sigma = 0.003;
  Measurements m;
  m.file = "synthetic";
  m.luminance.push_back(SyntheticLuminance("front_b", codes, 50.0, 0.01, 1.8, noise));
  CalibratedDisplay display;
  const CalibrationReport report = Calibrate(Designed(), m, CalibrationOptions{}, &display);
  ASSERT_TRUE(report.IsSolutionUsable()) << report.message;
  const testing::LuminanceSigma expected = testing::ExpectedLuminanceSigma(codes, 50.0, 0.01, 1.8, 0.003);
  EXPECT_LT(std::abs(display.find("front_b")->gamma - 1.8), kSigmas * expected.gamma);
  EXPECT_LT(std::abs(display.find("front_b")->black_level - 0.01), kSigmas * expected.black_level);
  EXPECT_LT(std::abs(display.find("front_b")->max_luminance - 50.0), kSigmas * expected.max_luminance);
  EXPECT_GT(report.luminance_rms_before, 10 * report.luminance_rms_after);
}

TEST(CalibrationTest, TwoLuminanceLevelsLeaveGammaUndetermined) {
  SyntheticNoise noise;
  Measurements m;
  m.file = "synthetic";
  m.luminance.push_back(SyntheticLuminance("rear_b", {0, 255}, 100.0, 0.01, 2.0, noise));
  CalibratedDisplay display;
  const CalibrationReport report = Calibrate(Designed(), m, CalibrationOptions{}, &display);
  ASSERT_TRUE(report.IsSolutionUsable()) << report.message;
  EXPECT_EQ(report.find("rear_b", "gamma")->status, ParameterStatus::kUndetermined);
  EXPECT_EQ(display.find("rear_b")->gamma, 2.4);
  EXPECT_TRUE(HasWarning(report, "panel \"rear_b\": luminance at fewer than three distinct input levels"));
}

TEST(CalibrationTest, MeasurementsOfAnotherDisplayAreRefused) {
  Measurements m;
  m.file = "m.json";
  m.luminance.push_back(SyntheticLuminance("rear", {0, 128, 255}, 100.0, 0.0, 2.2, SyntheticNoise{}));
  m.luminance.back().where = {"m.json", "/luminance/rear"};
  CalibratedDisplay display;
  const CalibrationReport report = Calibrate(Designed(), m, CalibrationOptions{}, &display);
  EXPECT_FALSE(report.IsSolutionUsable());
  EXPECT_EQ(report.message, "m.json: /luminance/rear: no panel named \"rear\" in " +
                                testing::ExamplePath("paper_prototype.json") + "; did you mean \"rear_a\"?");
}

TEST(CalibrationTest, InvalidOptionsAreReportedNotThrown) {
  Measurements m;
  m.luminance.push_back(SyntheticLuminance("rear_a", {0, 128, 255}, 100.0, 0.0, 2.2, SyntheticNoise{}));
  CalibrationOptions options;
  options.marker_loss_scale_rad = -1;
  CalibratedDisplay display;
  const CalibrationReport report = Calibrate(Designed(), m, options, &display);
  EXPECT_FALSE(report.IsSolutionUsable());
  EXPECT_EQ(report.message, "invalid options: marker_loss_scale: -1: must be a positive angle (rad)");
}

// ScalarFit directly: the Ceres paths that would abort if misused.
struct SumCost {
  double y;
  template <typename T>
  bool operator()(const T* a, const T* b, T* r) const {
    r[0] = *a + *b - T(y);
    return true;
  }
};

TEST(ScalarFitTest, RankDeficiencyHoldsOneParameterAndNamesItsPartner) {
  ScalarFit fit;
  const int a = fit.Add({"a", 1.0, 0, {}, {}});
  const int b = fit.Add({"b", 2.0, 1, {}, {}});
  for (double y : {5.0, 5.1, 4.9})
    fit.AddResidual(new ceres::AutoDiffCostFunction<SumCost, 1, 1, 1>(new SumCost{y}), nullptr, {a, b});
  const ScalarFitResult result = fit.Solve(ScalarFitOptions{});
  ASSERT_TRUE(result.usable);
  ASSERT_EQ(result.undetermined.size(), 1u);
  EXPECT_EQ(result.undetermined[0].index, a);  // the lower hold rank
  EXPECT_EQ(result.undetermined[0].partners, std::vector<int>{b});
  EXPECT_EQ(fit.value(a), 1.0);
  EXPECT_NEAR(fit.value(b), 4.0, 1e-7);
  ASSERT_EQ(result.covariance.rows(), 2);
  EXPECT_EQ(result.covariance(a, a), 0.0);
  // Var(mean of 3) with the residuals' own noise (0.1 over 2 degrees of freedom).
  EXPECT_NEAR(result.covariance(b, b), 0.01 / 3, 1e-9);
}

TEST(ScalarFitTest, InfeasibleHeldValueIsAFailedSolveNotACrash) {
  ScalarFit fit;
  const int a = fit.Add({"a", 5.0, 0, 0.0, 1.0});  // held outside its bounds
  const int b = fit.Add({"b", 0.0, 0, {}, {}});
  fit.Add({"unused", 0.0, 0, 0.0, 1.0});  // in no residual: its bounds must not reach Ceres
  fit.Hold(a);
  fit.AddResidual(new ceres::AutoDiffCostFunction<SumCost, 1, 1, 1>(new SumCost{1.0}), nullptr, {a, b});
  const ScalarFitResult result = fit.Solve(ScalarFitOptions{});
  EXPECT_FALSE(result.usable);
  EXPECT_NE(result.summary.message.find("infeasible"), std::string::npos) << result.summary.message;
  EXPECT_EQ(result.covariance.size(), 0);
}

// Issue 18: a value the data do not pin down is not reported as fitted.
// By hand: the bound of the model, and the stated fraction of the value.
TEST(UnresolvedTest, AtABoundOrBeyondTheStatedFractionByHand) {
  ScalarParameter distance{"the distance of panel \"p\"", 0.0728, 2, 7.5e-5, 0.075};
  ParameterEstimate p;
  p.quantity = "distance";
  p.value = 0.075;
  p.std_dev = 8.88e-5;
  EXPECT_EQ(Unresolved(distance, p),
            "ends at a bound of the model (75.0000 mm: the focal length, where its image is at infinity, 0 D)");
  p.value = 7.5e-5;
  EXPECT_EQ(Unresolved(distance, p), "ends at a bound of the model (0.0750 mm)");
  p.value = 0.0728;
  p.std_dev = 0.0766;  // the 76.6 mm of the issue
  EXPECT_EQ(Unresolved(distance, p),
            "has a standard deviation of 76.6000 mm, more than 10 % of its value (72.8000 mm)");
  p.std_dev = 0.1 * 0.0728 * 1.001;
  EXPECT_NE(Unresolved(distance, p), "");
  p.std_dev = 0.1 * 0.0728 * 0.999;
  EXPECT_EQ(Unresolved(distance, p), "");
  p.std_dev.reset();  // no uncertainty estimable: only the bound can tell
  EXPECT_EQ(Unresolved(distance, p), "");
  // An offset may well be zero: the fraction does not apply to it.
  ScalarParameter offset{"the offset x of panel \"p\"", 0, 4, {}, {}};
  p.quantity = "offset_x";
  p.value = 1e-6;
  p.std_dev = 1e-5;
  EXPECT_EQ(Unresolved(offset, p), "");
}

TEST(UnresolvedTest, TheExampleMeasurementsLeaveNothingUndetermined) {
  const Measurements m = ReadMeasurementsFile(testing::ExamplePath("paper_prototype_measurements.json"));
  CalibratedDisplay display;
  const CalibrationReport report = Calibrate(Designed(), m, CalibrationOptions{}, &display);
  ASSERT_TRUE(report.IsSolutionUsable()) << report.message;
  EXPECT_TRUE(report.unresolved.empty()) << report.FullReport();
  for (const ParameterEstimate& p : report.parameters) EXPECT_NE(p.status, ParameterStatus::kUnresolved);
}

// A panel whose markers span a smaller angle than any distance inside the
// focal length can show (its image at infinity subtends the least): the fit
// runs into the bound, the panel at the focal length (0 D), which was reported
// "fitted" before.
TEST(UnresolvedTest, APanelSeenTooSmallEndsAtTheFocalLengthAndIsUndetermined) {
  nlohmann::json doc = ReadJsonFile(testing::ExamplePath("paper_prototype_measurements.json"));
  const double cx = doc["camera"]["cx"], cy = doc["camera"]["cy"];
  for (auto& capture : doc["captures"])
    for (auto& marker : capture["markers"]["rear_a"]) {
      const double x = marker["camera_pixel"][0], y = marker["camera_pixel"][1];
      marker["camera_pixel"] = {cx + (x - cx) * 0.95, cy + (y - cy) * 0.95};
    }
  const Measurements m = ParseMeasurements(doc, "shrunk.json");
  // With the focal length and eye relief held as the scene has them (fitted, they take up the shrink instead,
  // and the fit puts rear_a beyond the focal length it finds: refused as not this display).
  CalibrationOptions held;
  held.focal_length = held.lens_gaps = FitChoice::kHold;
  CalibratedDisplay display;
  const CalibrationReport refused = Calibrate(Designed(), m, CalibrationOptions{}, &display);
  EXPECT_FALSE(refused.IsSolutionUsable());
  EXPECT_NE(refused.message.find("the measurements do not match this display"), std::string::npos) << refused.message;
  const CalibrationReport report = Calibrate(Designed(), m, held, &display);
  ASSERT_TRUE(report.IsSolutionUsable()) << report.message;
  const ParameterEstimate* distance = report.find("rear_a", "distance");
  ASSERT_NE(distance, nullptr);
  EXPECT_TRUE(testing::Close(distance->value, Designed().focal_length_m, 1e-6));
  EXPECT_EQ(distance->status, ParameterStatus::kUnresolved);
  EXPECT_EQ(report.find("rear_a", "virtual_depth")->status, ParameterStatus::kUnresolved);
  ASSERT_EQ(report.unresolved.size(), 1u) << report.FullReport();
  EXPECT_EQ(report.unresolved[0],
            "the distance of panel \"rear_a\": it ends at a bound of the model (75.0000 mm: the focal length, where "
            "its image is at infinity, 0 D)");
  EXPECT_TRUE(HasWarning(report, "it is reported undetermined, and `fit` writes no calibrated scene unless --force"));
  EXPECT_EQ(report.find("rear_b", "distance")->status, ParameterStatus::kFitted);
}

}  // namespace
}  // namespace layerlab
