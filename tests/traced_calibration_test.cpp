// The calibration fit through real lenses (calibration/traced_marker_model.h):
// the model sees each marker where the exact trace shows it, its parameters
// move what they should, and a prototype behind a real magnifier (Thorlabs
// LA1608, examples/paper_prototype_la1608.json) built off its design is
// recovered within the noise, where the first-order model calls the same
// measurements a model error.
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "layerlab/calibration/calibration.h"
#include "layerlab/calibration/synthetic_measurements.h"
#include "layerlab/calibration/traced_marker_model.h"
#include "layerlab/framework/json_file.h"
#include "layerlab/tests/calibration_test_util.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

using testing::kArcmin;

const DisplaySystem& Designed() {
  static const DisplaySystem system = Compile(LoadScene(testing::ExamplePath("paper_prototype_la1608.json")));
  return system;
}

// The designed parameters of layer k, with no optics fitted (the magnifier is its surfaces).
MarkerParameters<double> DesignedParameters(const VirtualLayer& layer) {
  MarkerParameters<double> q{layer.panel_distance_m,
                             layer.panel.eye_from_panel_m[0],
                             layer.panel.eye_from_panel_m[1],
                             layer.panel.rotation_rad,
                             0,
                             0,
                             0,
                             {},
                             {},
                             {}};
  for (const PathStep& s : layer.path)
    if (s.power_diopters != 0 && s.kind != ElementKind::kPanel) {
      q.gaps.push_back(0), q.focal_lengths.push_back(1 / s.power_diopters), q.distortions.push_back(0);
    }
  return q;
}

// Where a camera at `position`, turned as `camera` says, sees pixel (col, row) of `layer` in `system` (the exact
// trace inverted).
TracedMarker Seen(const DisplaySystem& system, const VirtualLayer& layer, const TracedLayerModel& model, double col,
                  double row, const std::array<double, 2>& position, const SyntheticCamera& camera = {}) {
  const std::array<double, 2> a = ImagedMarker(system, layer, col, row, camera, position);
  const MarkerPlacement m = PlaceMarker(layer, col, row, position[0], position[1]);
  const auto t = model.Prepare(m, a[0], a[1]);
  EXPECT_TRUE(t.has_value());
  return t.value_or(TracedMarker{});
}

// examples/relay_magnifier.json with its magnifier a real LA1608: behind the
// relay's inverted image, every layer's b < 0. Written beside the system's
// temporary files, so that testing::BuiltSystem reads this scene.
const DisplaySystem& InvertedBehindARealLens() {
  static const DisplaySystem system = [] {
    nlohmann::json scene = ReadJsonFile(testing::ExamplePath("relay_magnifier.json"));
    nlohmann::json& magnifier = testing::ElementNamed(scene, "magnifier");
    magnifier = {{"type", "lens"},
                 {"name", "magnifier"},
                 {"clear_aperture", "25.4 mm"},
                 {"surfaces",
                  {{{"radius", "38.6 mm"}, {"material", "N-BK7"}, {"thickness", "4.1 mm"}}, nlohmann::json::object()}},
                 {"next", magnifier["next"]}};
    scene.erase("solve"), scene.erase("run");  // their target scene lies beside the example
    const std::string file =
        (std::filesystem::temp_directory_path() / ("layerlab_relay_la1608_" + std::to_string(::getpid()) + ".json"))
            .string();
    std::ofstream(file) << scene.dump(1);
    return testing::CompileJson(scene, file);
  }();
  return system;
}

// The model, as designed, sees each marker of `layer` where the camera does, turned or not.
void ExpectTheModelSeesItsMarkers(const DisplaySystem& designed, const VirtualLayer& layer) {
  {
    ASSERT_TRUE(layer.ray_map) << layer.name;
    const TracedLayerModel model(layer, DesignedParameters(layer));
    // A camera turned (pan, tilt, roll) sees the markers elsewhere; the model turned alike sees them there.
    SyntheticCamera camera;
    camera.pan_rad = 0.01, camera.tilt_rad = -0.02, camera.roll_rad = 0.015;
    MarkerParameters<double> q = DesignedParameters(layer);
    q.pan = camera.pan_rad, q.tilt = camera.tilt_rad, q.roll = camera.roll_rad;
    const PanelSpec& p = layer.panel;
    for (const std::array<double, 2> position : {std::array<double, 2>{0, 0}, {2e-3, -1.5e-3}})
      for (const double u : {0.1, 0.5, 0.9})
        for (const double v : {0.15, 0.85}) {
          const double col = p.active_left + u * (p.active_cols - 1), row = p.active_top + v * (p.active_rows - 1);
          const TracedMarker m = Seen(designed, layer, model, col, row, position, camera);
          double e[2];
          ASSERT_TRUE(model.AngleError(q, m, e));
          EXPECT_LT(std::hypot(e[0], e[1]), 1e-9) << layer.name << " at (" << col << ", " << row << ")";
        }
  }
}

TEST(TracedCalibration, TheModelSeesEachMarkerWhereTheExactTraceShowsIt) {
  for (const DisplaySystem* designed : {&Designed(), &InvertedBehindARealLens()})
    for (const VirtualLayer& layer : designed->layers) {
      const bool inverted = designed != &Designed();
      EXPECT_EQ(layer.transfer.b < 0, inverted) << layer.name << ": inverted behind the relay, upright without it";
      ExpectTheModelSeesItsMarkers(*designed, layer);
    }
}

// Over markers of layer k of `built` seen from two camera positions: the
// largest error of the model under `right` and the least under the design.
struct ErrorRange {
  double worst_right = 0, least_designed = INFINITY;
};
ErrorRange ErrorsAgainstBuilt(const DisplaySystem& built, size_t k, const TracedLayerModel& model,
                              const MarkerParameters<double>& right, const MarkerParameters<double>& designed,
                              const std::array<double, 2>& off_axis, double row_fraction) {
  ErrorRange r;
  const PanelSpec& p = built.layers[k].panel;
  for (const std::array<double, 2> position : {std::array<double, 2>{0, 0}, off_axis})
    for (const double u : {0.1, 0.5, 0.9}) {
      const double col = p.active_left + u * (p.active_cols - 1),
                   row = p.active_top + row_fraction * (p.active_rows - 1);
      const TracedMarker m = Seen(built, built.layers[k], model, col, row, position);
      double e[2];
      EXPECT_TRUE(model.AngleError(right, m, e));
      r.worst_right = std::max(r.worst_right, std::hypot(e[0], e[1]));
      EXPECT_TRUE(model.AngleError(designed, m, e));
      r.least_designed = std::min(r.least_designed, std::hypot(e[0], e[1]));
    }
  return r;
}

// Each parameter, changed in the built display, is what the model needs to
// see the built display's markers: its error vanishes there (to the first
// order of the residual, well below the noise) and not at the design.
TEST(TracedCalibration, EachParameterMovesTheMarkersAsTheBuiltDisplayShowsThem) {
  const DisplaySystem& designed = Designed();
  const std::vector<testing::PanelTruth> truth = {
      {"rear_a", 0.4e-3, 0.3e-3, -0.2e-3, 0.3 * kRadiansPerDegree, 0, 0, 0}};
  const DisplaySystem built = testing::BuiltSystem(designed, truth);
  int k = 0;
  while (k < static_cast<int>(designed.layers.size()) && designed.layers[k].name != "rear_a") ++k;
  ASSERT_LT(k, static_cast<int>(designed.layers.size()));
  const VirtualLayer& layer = designed.layers[k];
  const TracedLayerModel model(layer, DesignedParameters(layer));
  MarkerParameters<double> right = DesignedParameters(built.layers[k]);
  right.gaps = DesignedParameters(layer).gaps;
  const ErrorRange r = ErrorsAgainstBuilt(built, k, model, right, DesignedParameters(layer), {3e-3, 0}, 0.3);
  EXPECT_LT(r.worst_right, 1e-4 * kArcmin);
  EXPECT_GT(r.least_designed, 3 * kArcmin);
}

// A fitted gap moves its element and everything behind it: the relay's far
// lens built 0.4 mm farther, with the panels kept at their distances from it,
// is what the model sees with that gap changed by 0.4 mm, and not as designed.
TEST(TracedCalibration, AGapMovesItsLensAndWhatLiesBehindIt) {
  const DisplaySystem& designed = InvertedBehindARealLens();
  const DisplaySystem built = testing::BuiltSystem(designed, {}, {{"relay_far", 0.4e-3, std::nullopt}});
  for (size_t k = 0; k < designed.layers.size(); ++k) {
    const VirtualLayer& layer = designed.layers[k];
    const TracedLayerModel model(layer, DesignedParameters(layer));
    MarkerParameters<double> right = DesignedParameters(layer);
    int far = -1, j = 0;
    for (const PathStep& s : layer.path)
      if (s.power_diopters != 0 && s.kind != ElementKind::kPanel) far = s.element == "relay_far" ? j : far, ++j;
    ASSERT_GE(far, 0);
    right.gaps[far] += 0.4e-3;
    const ErrorRange r = ErrorsAgainstBuilt(built, k, model, right, DesignedParameters(layer), {2e-3, 1e-3}, 0.7);
    EXPECT_LT(r.worst_right, 1e-4 * kArcmin) << layer.name;
    EXPECT_GT(r.least_designed, 0.03 * kArcmin) << layer.name;  // 0.053 arcmin at the 0.4 D layer's centre
  }
}

testing::SyntheticSetup TracedSetup(double sigma_arcmin) {
  testing::SyntheticSetup setup = testing::ExampleSetup();
  setup.camera.intrinsics.reset();
  setup.camera.positions_m = {{0.0, 0.0}, {2e-3, 0.0}, {0.0, 2e-3}, {-2e-3, 0.0}};
  setup.noise.marker_sigma_rad = sigma_arcmin * kArcmin;
  setup.luminance_codes.clear();
  return setup;
}

TEST(TracedCalibration, WithoutNoiseRecoversAPrototypeBehindARealLensExactly) {
  const std::vector<testing::PanelTruth> truth = testing::ExampleTruth();
  const DisplaySystem built = testing::BuiltSystem(Designed(), truth);
  const Measurements m = testing::SyntheticMeasurements(built, truth, TracedSetup(0));
  CalibratedDisplay display;
  const CalibrationReport report = Calibrate(Designed(), m, CalibrationOptions{}, &display);
  ASSERT_TRUE(report.IsSolutionUsable()) << report.FullReport();
  testing::ExpectPlacementsOf(built, display, 1e-8);
  EXPECT_LT(report.marker_rms_after_rad, 1e-6 * kArcmin);
}

TEST(TracedCalibration, RecoversAPrototypeBehindARealLensWithinTheNoise) {
  const std::vector<testing::PanelTruth> truth = testing::ExampleTruth();
  const DisplaySystem built = testing::BuiltSystem(Designed(), truth);
  const testing::SyntheticSetup setup = TracedSetup(0.3);
  const Measurements m = testing::SyntheticMeasurements(built, truth, setup);
  CalibratedDisplay display;
  const CalibrationReport report = Calibrate(Designed(), m, CalibrationOptions{}, &display);
  ASSERT_TRUE(report.IsSolutionUsable()) << report.FullReport();
  EXPECT_TRUE(testing::Close(report.marker_rms_after_rad, std::sqrt(2.0) * setup.noise.marker_sigma_rad, 0.15))
      << report.FullReport();
  for (const VirtualLayer& layer : built.layers) {
    const std::pair<const char*, double> values[] = {{"distance", layer.panel_distance_m},
                                                     {"offset_x", layer.panel.eye_from_panel_m[0]},
                                                     {"offset_y", layer.panel.eye_from_panel_m[1]},
                                                     {"rotation", layer.panel.rotation_rad},
                                                     {"virtual_depth", layer.diopters}};
    for (const auto& [quantity, value] : values) {
      const ParameterEstimate* e = report.find(layer.name, quantity);
      ASSERT_TRUE(e && e->std_dev) << layer.name << " " << quantity;
      EXPECT_LT(std::abs(e->value - value), 3 * *e->std_dev)
          << layer.name << " " << quantity << ": " << e->value << " +- " << *e->std_dev << ", truth " << value;
    }
  }
  // The magnifier is its surfaces: traced, not fitted.
  const ParameterEstimate* f = report.find("lens", "focal_length");
  ASSERT_NE(f, nullptr);
  EXPECT_EQ(f->status, ParameterStatus::kNotFitted);
}

}  // namespace
}  // namespace layerlab
