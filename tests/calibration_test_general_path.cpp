// Calibration on optical paths other than the paper's single magnifier
// (issue 16): each branch its own lens (examples/per_branch_magnifiers.json),
// a relay that inverts the image, no optics at all. The synthetic markers are
// checked against a ray traced element by element; the fit's gaps, distances
// and their reported uncertainties against the truth and against a brute-force
// covariance from recompiled scenes (tests/calibration_test_util.h).
#include <cmath>
#include <numbers>

#include "layerlab/calibration/calibrated_scene.h"
#include "layerlab/calibration/calibration.h"
#include "layerlab/calibration/marker_model.h"
#include "layerlab/framework/atomic_file.h"
#include "layerlab/tests/calibration_test_util.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

using nlohmann::json;
using testing::OpticTruth;
using testing::PanelTruth;
using testing::SyntheticSetup;

using testing::kArcmin;
using testing::kSigmas;

DisplaySystem Example(const std::string& name) { return Compile(LoadScene(testing::ExamplePath(name))); }

const DisplaySystem& PerBranch() {
  static const DisplaySystem system = Example("per_branch_magnifiers.json");
  return system;
}

SyntheticSetup AnglesOnly(double sigma_arcmin) {
  SyntheticSetup setup = testing::PerBranchSetup();
  setup.camera.intrinsics.reset();
  setup.noise.marker_sigma_rad = sigma_arcmin * kArcmin;
  return setup;
}

CalibrationOptions LensGaps() {
  CalibrationOptions options;
  options.lens_gaps = FitChoice::kFit;
  options.focal_length = FitChoice::kHold;  // the uncertainties below are derived with the focal lengths known
  return options;
}

// The slope (tan-angle) of the paraxial ray from pupil point `c` that lands at
// unfolded height `target` on the panel: stepped element by element (free
// space y += t u, a thin element u -= P y), linear in the slope it starts with.
double TracedSlope(const VirtualLayer& layer, double c, double target) {
  auto land = [&](double u) {
    double y = c, z = 0;
    for (const PathStep& s : layer.path) {
      if (s.power_diopters == 0) continue;
      y += (*s.position_m - z) * u;
      z = *s.position_m;
      u -= s.power_diopters * y;
    }
    return y + (layer.position_m - z) * u;
  };
  const double h0 = land(0), h1 = land(1);
  return (target - h0) / (h1 - h0);
}

TEST(GeneralPathCalibrationTest, SyntheticMarkersMatchARayTracedThroughTheElements) {
  const std::vector<PanelTruth> truth = testing::PerBranchTruth();
  for (const DisplaySystem& built : {testing::BuiltSystem(PerBranch(), truth, testing::PerBranchOptics()),
                                     Example("relay_magnifier.json"), Example("tensor_display_3layer.json")}) {
    int checked = 0;
    for (const VirtualLayer& layer : built.layers) {
      const PanelSpec& p = layer.panel;
      for (double col : {p.active_left + 3.0, p.active_left + p.active_cols - 5.0})
        for (double row : {p.active_top + 2.0, p.active_top + p.active_rows - 4.0})
          for (const std::array<double, 2>& camera : {std::array<double, 2>{0, 0}, {2.5e-3, -1.5e-3}}) {
            const MarkerPlacement m = PlaceMarker(layer, col, row, camera[0], camera[1]);
            const double c = std::cos(p.rotation_rad), s = std::sin(p.rotation_rad);
            // Eye-space orientation; an inverted image turns it by 180 degrees in the unfolded path.
            const double turn = layer.inverted ? -1.0 : 1.0;
            const double x = turn * (p.eye_from_panel_m[0] + c * m.local_x_m - s * m.local_y_m);
            const double y = turn * (p.eye_from_panel_m[1] + s * m.local_x_m + c * m.local_y_m);
            const auto angle = ImagedMarker(built, layer, col, row, SyntheticCamera{}, camera);
            EXPECT_NEAR(angle[0], std::atan(TracedSlope(layer, camera[0], x)), 1e-12)
                << built.file << " " << layer.name;
            EXPECT_NEAR(angle[1], std::atan(TracedSlope(layer, camera[1], y)), 1e-12)
                << built.file << " " << layer.name;
            ++checked;
          }
    }
    EXPECT_GE(checked, 16) << built.file;
  }
}

// The marker model's composition for lens_a's branch, written out by hand:
// the lens 15 mm behind the half mirror, itself 15 mm from the pupil.
TEST(GeneralPathCalibrationTest, MarkerModelComposesTheGapsAndFocalLengths) {
  const LayerOptics optics{{0}, {15e-3}};
  MarkerParameters<double> q{52e-3, 0, 0, 0, 0, 0, 0, {15.4e-3}, {61e-3}, {0.0}};
  const RayTransfer<double> m = LayerTransfer(optics, q);
  // T(e) then L(1/f) then T(s): a = 1 - s/f, b = e + s (1 - e/f).
  const double e = 30.4e-3, f = 61e-3, s = 52e-3;
  EXPECT_NEAR(m.a, 1 - s / f, 1e-15);
  EXPECT_NEAR(m.b, e + s * (1 - e / f), 1e-15);
  const MarkerPlacement marker{1e-3, -2e-3, 2e-3, 1e-3};
  double angle[2];
  PredictVisualAngle(q, optics, marker, angle);
  EXPECT_NEAR(angle[0], std::atan(1e-3 / m.b - 2e-3 * m.a / m.b), 1e-15);
  EXPECT_NEAR(angle[1], std::atan(-2e-3 / m.b - 1e-3 * m.a / m.b), 1e-15);
}

TEST(GeneralPathCalibrationTest, WithoutNoiseRecoversEachBranchsLensGapExactly) {
  const std::vector<PanelTruth> truth = testing::PerBranchTruth();
  const DisplaySystem built = testing::BuiltSystem(PerBranch(), truth, testing::PerBranchOptics());
  const Measurements m = testing::SyntheticMeasurements(built, truth, AnglesOnly(0));
  for (bool focal_lengths_too : {false, true}) {
    CalibrationOptions options = LensGaps();
    options.focal_length = focal_lengths_too ? FitChoice::kFit : FitChoice::kHold;
    CalibratedDisplay display;
    const CalibrationReport report = Calibrate(PerBranch(), m, options, &display);
    ASSERT_TRUE(report.IsSolutionUsable()) << report.message;
    EXPECT_LT(report.marker_rms_after_rad, 1e-10) << report.FullReport();
    for (const char* lens : {"lens_a", "lens_b"}) {
      const ParameterEstimate* gap = report.find(lens, "gap");
      ASSERT_NE(gap, nullptr) << lens;
      EXPECT_EQ(gap->status, ParameterStatus::kFitted) << lens;
      const double designed = 15e-3;  // both lenses 15 mm behind the half mirror
      EXPECT_NEAR(gap->scene_value, designed, 1e-15);
      const double change = std::string(lens) == "lens_a" ? 0.5e-3 : -0.4e-3;
      EXPECT_NEAR(gap->value, designed + change, 1e-9) << lens;
      EXPECT_NEAR(display.find_optic(lens)->focal_length_m, std::string(lens) == "lens_a" ? 60e-3 : 80e-3, 1e-9);
      EXPECT_EQ(report.find(lens, "focal_length")->status,
                focal_lengths_too ? ParameterStatus::kFitted : ParameterStatus::kNotFitted);
    }
    testing::ExpectPlacementsOf(built, display, 1e-9);
    for (const VirtualLayer& layer : built.layers)
      EXPECT_NEAR(report.find(layer.name, "virtual_depth")->value, layer.diopters, 1e-7) << layer.name;
  }
}

// Issue 16's test: each branch's lens gap within 4 reported standard
// deviations, and those standard deviations what the noise and the marker
// layout give (a brute-force covariance over the same parameters).
TEST(GeneralPathCalibrationTest, RecoversEachBranchsLensGapWithinTheNoise) {
  const std::vector<PanelTruth> truth = testing::PerBranchTruth();
  const std::vector<OpticTruth> optics = testing::PerBranchOptics();
  const json built_scene = testing::BuiltScene(PerBranch(), truth, optics);
  const DisplaySystem built = testing::CompileJson(built_scene, PerBranch().file);
  const double sigma = 0.3 * kArcmin;

  // The brute-force uncertainties: every parameter the fit frees, changed in the built scene.
  std::vector<testing::SceneParameter> parameters;
  for (const OpticTruth& o : optics) {
    json copy = built_scene;
    const double at = std::stod(testing::ElementNamed(copy, o.name)["gap"].get<std::string>());  // "0.0155 m"
    parameters.push_back({o.name + " gap", 1e-6, [o, at](json& s, double d) {
                            testing::ElementNamed(s, o.name)["gap"] = testing::Exact(at + d, "m");
                          }});
  }
  for (const VirtualLayer& layer : built.layers) {
    const std::string name = layer.name;
    const double s0 = layer.panel_distance_m, x0 = layer.panel.eye_from_panel_m[0],
                 y0 = layer.panel.eye_from_panel_m[1], r0 = layer.panel.rotation_rad;
    parameters.push_back({name + " distance", 1e-6, [=](json& s, double d) {
                            testing::ElementNamed(s, name)["distance"] = testing::Exact(s0 + d, "m");
                          }});
    parameters.push_back(
        {name + " offset_x", 1e-6, [=](json& s, double d) {
           testing::ElementNamed(s, name)["offset"] = {testing::Exact(x0 + d, "m"), testing::Exact(y0, "m")};
         }});
    parameters.push_back(
        {name + " offset_y", 1e-6, [=](json& s, double d) {
           testing::ElementNamed(s, name)["offset"] = {testing::Exact(x0, "m"), testing::Exact(y0 + d, "m")};
         }});
    parameters.push_back({name + " rotation", 1e-5, [=](json& s, double d) {
                            testing::ElementNamed(s, name)["rotation"] = testing::Exact(r0 + d, "rad");
                          }});
  }
  const std::vector<double> expected = testing::BruteForceSigmas(built_scene, parameters, AnglesOnly(0), sigma);
  ASSERT_LT(expected[0], 0.5e-3) << "the setup should see each lens gap to better than half a millimeter";

  for (uint64_t seed : {1u, 2u, 3u}) {
    SyntheticSetup setup = AnglesOnly(0.3);
    setup.noise.seed = seed;
    const Measurements m = testing::SyntheticMeasurements(built, truth, setup);
    CalibratedDisplay display;
    const CalibrationReport report = Calibrate(PerBranch(), m, LensGaps(), &display);
    ASSERT_TRUE(report.IsSolutionUsable()) << report.message;
    EXPECT_TRUE(report.warnings.empty()) << report.FullReport();
    EXPECT_TRUE(testing::Close(report.marker_noise_rad, sigma, 0.15)) << report.FullReport();
    size_t i = 0;
    for (const OpticTruth& o : optics) {
      const ParameterEstimate* gap = report.find(o.name, "gap");
      ASSERT_NE(gap, nullptr);
      ASSERT_EQ(gap->status, ParameterStatus::kFitted);
      ASSERT_TRUE(gap->std_dev.has_value());
      const double truth_gap = gap->scene_value + o.gap_change;
      EXPECT_LT(std::abs(gap->value - truth_gap), kSigmas * *gap->std_dev) << o.name << " seed " << seed << "\n"
                                                                           << report.FullReport();
      EXPECT_TRUE(*gap->std_dev > 0.7 * expected[i] && *gap->std_dev < 1.3 * expected[i])
          << o.name << ": reported " << *gap->std_dev << ", brute force " << expected[i];
      ++i;
    }
    for (const VirtualLayer& layer : built.layers) {
      const CalibratedPanel* p = display.find(layer.name);
      const double values[] = {p->distance_m, p->eye_from_panel_x_m, p->eye_from_panel_y_m, p->rotation_rad};
      const double truths[] = {layer.panel_distance_m, layer.panel.eye_from_panel_m[0], layer.panel.eye_from_panel_m[1],
                               layer.panel.rotation_rad};
      const char* quantities[] = {"distance", "offset_x", "offset_y", "rotation"};
      for (int q = 0; q < 4; ++q, ++i) {
        EXPECT_LT(std::abs(values[q] - truths[q]), kSigmas * expected[i]) << parameters[i].name << " seed " << seed;
        const ParameterEstimate* e = report.find(layer.name, quantities[q]);
        ASSERT_TRUE(e && e->std_dev);
        EXPECT_TRUE(*e->std_dev > 0.7 * expected[i] && *e->std_dev < 1.3 * expected[i])
            << parameters[i].name << ": reported " << *e->std_dev << ", brute force " << expected[i];
      }
    }
  }
}

TEST(GeneralPathCalibrationTest, LensGapsWithoutParallaxAreUndetermined) {
  const std::vector<PanelTruth> truth = testing::PerBranchTruth();
  const DisplaySystem built = testing::BuiltSystem(PerBranch(), truth, testing::PerBranchOptics());
  SyntheticSetup setup = AnglesOnly(0.3);
  setup.camera.positions_m = {{0.0, 0.0}};
  const Measurements m = testing::SyntheticMeasurements(built, truth, setup);
  CalibrationOptions options = LensGaps();
  options.focal_length = FitChoice::kFit;
  CalibratedDisplay display;
  const CalibrationReport report = Calibrate(PerBranch(), m, options, &display);
  ASSERT_TRUE(report.IsSolutionUsable()) << report.message;
  for (const char* lens : {"lens_a", "lens_b"})
    for (const char* quantity : {"gap", "focal_length"}) {
      const ParameterEstimate* p = report.find(lens, quantity);
      ASSERT_NE(p, nullptr);
      EXPECT_EQ(p->status, ParameterStatus::kUndetermined) << lens << " " << quantity;
      EXPECT_EQ(p->value, p->scene_value);
      EXPECT_FALSE(p->std_dev.has_value());
    }
  bool warned = false;
  for (const std::string& w : report.warnings)
    warned = warned || w == "the gap of \"lens_a\" cannot be told from the panel distances while each panel behind it "
                            "is seen from one camera position only: it keeps its scene value (15.0000 mm); add "
                            "captures from other camera positions (\"camera_position\") to fit it";
  EXPECT_TRUE(warned) << report.FullReport();
  EXPECT_FALSE(display.find_optic("lens_a")->gap_fitted);
}

// One panel behind each lens: its distance and the lens gap and focal length
// trade off (two numbers, scale and image depth, for three): one is held, named.
TEST(GeneralPathCalibrationTest, OnePanelBehindALensCannotFixItsGapAndFocalLength) {
  const std::vector<PanelTruth> truth = testing::PerBranchTruth();
  const DisplaySystem built = testing::BuiltSystem(PerBranch(), truth, testing::PerBranchOptics());
  Measurements m = testing::SyntheticMeasurements(built, truth, AnglesOnly(0.3));
  for (Capture& c : m.captures)
    std::erase_if(c.panels, [](const PanelMarkers& p) { return p.panel == "rear_a" || p.panel == "rear_b"; });
  CalibrationOptions options = LensGaps();
  options.focal_length = FitChoice::kFit;
  CalibratedDisplay display;
  const CalibrationReport report = Calibrate(PerBranch(), m, options, &display);
  ASSERT_TRUE(report.IsSolutionUsable()) << report.message;
  int undetermined = 0;
  for (const char* lens : {"lens_a", "lens_b"})
    for (const char* quantity : {"gap", "focal_length"})
      undetermined += report.find(lens, quantity)->status == ParameterStatus::kUndetermined;
  EXPECT_EQ(undetermined, 2) << report.FullReport();
  bool named = false;
  for (const std::string& w : report.warnings) named = named || w.find("the data do not determine the") == 0;
  EXPECT_TRUE(named) << report.FullReport();
}

// The calibrated scene: the fitted gaps land on the lenses' "gap", every panel
// gets its distance from its lens in the place of "virtual_depth", and the
// scene compiles to the display as built.
TEST(GeneralPathCalibrationTest, CalibratedSceneCompilesToTheDisplayAsBuilt) {
  const std::vector<PanelTruth> truth = testing::PerBranchTruth();
  const DisplaySystem built = testing::BuiltSystem(PerBranch(), truth, testing::PerBranchOptics());
  const Measurements m = testing::SyntheticMeasurements(built, truth, AnglesOnly(0));
  CalibrationOptions options = LensGaps();
  options.focal_length = FitChoice::kFit;
  CalibratedDisplay display;
  const CalibrationReport report = Calibrate(PerBranch(), m, options, &display);
  ASSERT_TRUE(report.IsSolutionUsable()) << report.message;
  const std::string path = testing::ExamplePath("per_branch_magnifiers.json");
  const nlohmann::ordered_json input = ReadDocumentInOrder(path);
  const nlohmann::ordered_json document = CalibratedSceneDocument(input, path, display);
  EXPECT_EQ(input, ReadDocumentInOrder(path));
  const auto& elements = document["elements"];
  EXPECT_EQ(elements[2]["name"], "lens_a");
  EXPECT_EQ(std::next(elements[2].begin(), 3).key(), "gap");  // in its place
  EXPECT_EQ(elements[3]["name"], "front_a");
  EXPECT_EQ(std::next(elements[3].begin(), 2).key(), "distance");
  EXPECT_FALSE(elements[3].contains("virtual_depth"));
  const DisplaySystem calibrated = testing::CompileJson(json::parse(document.dump()), "calibrated.json");
  ASSERT_EQ(calibrated.layers.size(), built.layers.size());
  for (size_t k = 0; k < built.layers.size(); ++k) {
    EXPECT_EQ(calibrated.layers[k].name, built.layers[k].name);
    EXPECT_NEAR(calibrated.layers[k].position_m, built.layers[k].position_m, 1e-9) << built.layers[k].name;
    EXPECT_NEAR(calibrated.layers[k].diopters, built.layers[k].diopters, 1e-6) << built.layers[k].name;
    EXPECT_NEAR(calibrated.layers[k].rotation_rad, built.layers[k].rotation_rad, 1e-9) << built.layers[k].name;
  }
}

// Without optics the panels are placed by "gap" from the one in front: the
// calibrated scene keeps that form, the gaps counted between fitted places.
TEST(GeneralPathCalibrationTest, PanelsWithoutOpticsKeepTheirGaps) {
  const DisplaySystem designed = Example("tensor_display_3layer.json");
  const std::vector<PanelTruth> truth = {{"front", 0.6e-3, 0.1e-3, 0, 0.1 * std::numbers::pi / 180, 0, 0, 0},
                                         {"middle", -0.3e-3, 0, 0.2e-3, 0, 0, 0, 0},
                                         {"rear", 0.4e-3, -0.1e-3, 0, -0.2 * std::numbers::pi / 180, 0, 0, 0}};
  const DisplaySystem built = testing::BuiltSystem(designed, truth);
  SyntheticSetup setup = AnglesOnly(0);
  const Measurements m = testing::SyntheticMeasurements(built, truth, setup);
  CalibratedDisplay display;
  const CalibrationReport report = Calibrate(designed, m, CalibrationOptions{}, &display);
  ASSERT_TRUE(report.IsSolutionUsable()) << report.message;
  EXPECT_LT(report.marker_rms_after_rad, 1e-10) << report.FullReport();
  const std::string path = testing::ExamplePath("tensor_display_3layer.json");
  const nlohmann::ordered_json document = CalibratedSceneDocument(ReadDocumentInOrder(path), path, display);
  for (const auto& e : document["elements"])
    if (e["type"] == "lc_panel") {
      EXPECT_TRUE(e.contains("gap")) << e.dump();
      EXPECT_FALSE(e.contains("distance")) << e.dump();
    }
  const DisplaySystem calibrated = testing::CompileJson(json::parse(document.dump()), "calibrated.json");
  for (size_t k = 0; k < built.layers.size(); ++k)
    EXPECT_NEAR(calibrated.layers[k].position_m, built.layers[k].position_m, 1e-9) << built.layers[k].name;
}

// A fold mirror between lens_a and front_a, front_a placed by "gap" from it:
// a fitted lens gap moves the mirror and the panel with it, so the panel's
// gap is counted from where the fitted lens puts the mirror.
TEST(GeneralPathCalibrationTest, PanelGapBehindAFoldFollowsTheFittedLens) {
  json scene = testing::ReadExample("per_branch_magnifiers.json");
  testing::ElementNamed(scene, "lens_a")["next"] = "fold";
  scene["elements"].push_back({{"type", "mirror"}, {"name", "fold"}, {"gap", "20 mm"}, {"next", "front_a"}});
  json& front = testing::ElementNamed(scene, "front_a");
  front.erase("virtual_depth");
  front["gap"] = "32 mm";
  const std::string file = ::testing::TempDir() + "/folded_per_branch.json";
  WriteFileAtomically(file, scene.dump(2));
  const DisplaySystem designed = Compile(LoadScene(file));
  const std::vector<PanelTruth> truth = testing::PerBranchTruth();
  const DisplaySystem built = testing::BuiltSystem(designed, truth, testing::PerBranchOptics());
  const Measurements m = testing::SyntheticMeasurements(built, truth, AnglesOnly(0));
  CalibratedDisplay display;
  const CalibrationReport report = Calibrate(designed, m, LensGaps(), &display);
  ASSERT_TRUE(report.IsSolutionUsable()) << report.message;
  EXPECT_LT(report.marker_rms_after_rad, 1e-10) << report.FullReport();
  const nlohmann::ordered_json document = CalibratedSceneDocument(ReadDocumentInOrder(file), file, display);
  json written = json::parse(document.dump());
  EXPECT_TRUE(testing::ElementNamed(written, "front_a").contains("gap"));
  const DisplaySystem calibrated = testing::CompileJson(written, "calibrated.json");
  for (size_t k = 0; k < built.layers.size(); ++k)
    EXPECT_NEAR(calibrated.layers[k].position_m, built.layers[k].position_m, 1e-9) << built.layers[k].name;
}

// Through a 4f relay the images are inverted (B < 0): the fit sees the panels
// turned by 180 degrees and still recovers them, to the last digits without noise.
TEST(GeneralPathCalibrationTest, RecoversPanelsSeenInvertedThroughARelay) {
  const DisplaySystem designed = Example("relay_magnifier.json");
  ASSERT_TRUE(designed.layers[0].inverted && designed.layers[1].inverted);
  const std::vector<PanelTruth> truth = {{"front", 0.2e-3, 0.1e-3, -0.2e-3, 0.2 * std::numbers::pi / 180, 0, 0, 0},
                                         {"rear", -0.3e-3, -0.15e-3, 0.1e-3, -0.1 * std::numbers::pi / 180, 0, 0, 0}};
  const DisplaySystem built = testing::BuiltSystem(designed, truth);
  const Measurements m = testing::SyntheticMeasurements(built, truth, AnglesOnly(0));
  CalibratedDisplay display;
  const CalibrationReport report = Calibrate(designed, m, CalibrationOptions{}, &display);
  ASSERT_TRUE(report.IsSolutionUsable()) << report.message;
  EXPECT_GT(report.marker_rms_before_rad, 5 * kArcmin);
  EXPECT_LT(report.marker_rms_after_rad, 1e-10) << report.FullReport();
  testing::ExpectPlacementsOf(built, display, 1e-9);
  EXPECT_TRUE(report.warnings.empty()) << report.FullReport();
}

}  // namespace
}  // namespace layerlab
