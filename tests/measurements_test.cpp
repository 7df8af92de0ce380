// The measurements file: bad input refused with the file and JSON pointer
// (messages asserted verbatim), the example file traced to its known truth,
// and the calibrated scene it yields read back by the scene loader.
//
// examples/paper_prototype_measurements.json is generated from
// ExampleTruth() and ExampleSetup() (tests/calibration_test_util.h). After
// changing either, regenerate it with
//   LAYERLAB_REGENERATE_EXAMPLES=1 build/tests/calibration_tests --gtest_filter='ExampleMeasurements.*'
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <functional>

#include "layerlab/calibration/calibrated_scene.h"
#include "layerlab/calibration/calibration.h"
#include "layerlab/framework/atomic_file.h"
#include "layerlab/framework/json_file.h"
#include "layerlab/tests/calibration_test_util.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

using nlohmann::json;

const char* kExample = "paper_prototype_measurements.json";

// The markers of `panel` in capture `c` (a file read back lists panels in its own order).
const PanelMarkers& MarkersOf(const Measurements& m, size_t c, const std::string& panel) {
  for (const PanelMarkers& p : m.captures[c].panels)
    if (p.panel == panel) return p;
  throw std::runtime_error("no markers of " + panel);
}

const PanelLuminance& LuminanceOf(const Measurements& m, const std::string& panel) {
  for (const PanelLuminance& l : m.luminance)
    if (l.panel == panel) return l;
  throw std::runtime_error("no luminance of " + panel);
}

const DisplaySystem& Designed() {
  static const DisplaySystem system = Compile(LoadScene(testing::ExamplePath("paper_prototype.json")));
  return system;
}

json SmallValid() {
  return json::parse(R"({
    "format": "layerlab-measurements/1",
    "camera": {"fx": 3000, "fy": 3000, "cx": 2000, "cy": 1500},
    "captures": [{"markers": {"rear_a": [{"panel_pixel": [500, 320], "camera_pixel": [1500.25, 1400.5]},
                                         {"panel_pixel": [780, 460], "angle": ["0.5 deg", "-1 deg"]}]}}],
    "luminance": {"rear_a": {"levels": "8-bit", "samples": [[0, 0.3], [128, 20], [255, 80]]}}
  })");
}

std::string ParseError(const json& document) {
  try {
    ParseMeasurements(document, "m.json");
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(MeasurementsTest, ReadsPixelsAndAngles) {
  const Measurements m = ParseMeasurements(SmallValid(), "m.json");
  ASSERT_EQ(m.captures.size(), 1u);
  const MarkerObservation& pixel = m.captures[0].panels[0].markers[0];
  EXPECT_NEAR(pixel.angle_x, std::atan(-499.75 / 3000), 1e-12);
  EXPECT_NEAR(pixel.angle_y, std::atan(99.5 / 3000), 1e-12);  // v counts down, the angle up
  const MarkerObservation& angle = m.captures[0].panels[0].markers[1];
  EXPECT_NEAR(angle.angle_y, -M_PI / 180, 1e-15);
  EXPECT_EQ(m.luminance[0].samples[1].level, 128.0 / 255.0);
  EXPECT_NO_THROW(CheckMeasurements(m, Designed()));
}

// The marker model is first order: a tilted panel is refused by the fit with
// the panel, its "tilt" and the reason, not fitted as if square to the axis.
TEST(MeasurementsTest, ATiltedPanelIsRefusedByTheCalibrationFit) {
  json scene = ReadJsonFile(testing::ExamplePath("paper_prototype.json"));
  scene["elements"][4]["tilt"] = {"0.5 deg", "0 deg"};
  const DisplaySystem tilted = testing::CompileJson(scene, "tilted.json");
  CalibratedDisplay display;
  const CalibrationReport report =
      Calibrate(tilted, ParseMeasurements(SmallValid(), "m.json"), CalibrationOptions{}, &display);
  EXPECT_FALSE(report.IsSolutionUsable());
  EXPECT_EQ(report.message, "tilted.json: panel \"" + scene["elements"][4]["name"].get<std::string>() +
                                "\" has \"tilt\" [0.500, 0.000] deg, which the calibration fit cannot represent: its "
                                "marker model is first order (a panel square to the axis, placed by its distance, "
                                "offset and in-plane rotation); leave \"tilt\" out of the scene for it");
  EXPECT_NO_THROW(CheckMeasurements(ParseMeasurements(SmallValid(), "m.json"), Designed()));
}

struct BadMeasurements {
  std::string name;
  std::function<void(json&)> mutate;
  std::string message;
};

void PrintTo(const BadMeasurements& c, std::ostream* os) { *os << c.name; }

class BadMeasurementsTest : public ::testing::TestWithParam<BadMeasurements> {};

TEST_P(BadMeasurementsTest, IsRefusedWithItsLocation) {
  json document = SmallValid();
  GetParam().mutate(document);
  std::string error = ParseError(document);
  if (error.empty()) {
    try {
      CheckMeasurements(ParseMeasurements(document, "m.json"), Designed());
    } catch (const Error& e) {
      error = e.what();
    }
  }
  EXPECT_EQ(error, GetParam().message);
}

const BadMeasurements kBad[] = {
    {"WrongFormat", [](json& d) { d["format"] = "layerlab-scene/1"; },
     "m.json: /format: unknown measurements format \"layerlab-scene/1\"; this layerlab reads "
     "\"layerlab-measurements/1\""},
    {"MisspelledKey",
     [](json& d) {
       d["captures"][0]["markers"]["rear_a"][0]["panel_pixle"] = {1, 2};
     },
     "m.json: /captures/0/markers/rear_a/0/panel_pixle: unknown key \"panel_pixle\"; did you mean \"panel_pixel\"?"},
    {"MarkerAsNumber", [](json& d) { d["captures"][0]["markers"]["rear_a"][1] = 3; },
     "m.json: /captures/0/markers/rear_a/1: expected an object, got a number"},
    {"PixelNotAPair",
     [](json& d) {
       d["captures"][0]["markers"]["rear_a"][0]["panel_pixel"] = {1, 2, 3};
     },
     "m.json: /captures/0/markers/rear_a/0/panel_pixel: expected two values [col, row], got an array [1,2,3]"},
    {"PixelNotANumber", [](json& d) { d["captures"][0]["markers"]["rear_a"][0]["camera_pixel"][1] = "12"; },
     "m.json: /captures/0/markers/rear_a/0/camera_pixel/1: expected a number, got a string"},
    {"NoImage", [](json& d) { d["captures"][0]["markers"]["rear_a"][0].erase("camera_pixel"); },
     "m.json: /captures/0/markers/rear_a/0: missing the marker's image: give \"camera_pixel\": [u, v] or "
     "\"angle\": [x, y]"},
    {"PixelWithoutCamera", [](json& d) { d.erase("camera"); },
     "m.json: /captures/0/markers/rear_a/0/camera_pixel: a camera pixel needs the camera's intrinsics: add "
     "\"camera\": {\"fx\", \"fy\", \"cx\", \"cy\"} at the top level, or give \"angle\" instead"},
    {"NegativeFocal", [](json& d) { d["camera"]["fx"] = -3000; },
     "m.json: /camera/fx: the focal length in pixels must be positive"},
    {"EmptyMarkers", [](json& d) { d["captures"][0]["markers"]["rear_a"] = json::array(); },
     "m.json: /captures/0/markers/rear_a: an empty list of markers; leave the panel out instead"},
    {"LevelOutOfRange", [](json& d) { d["luminance"]["rear_a"]["samples"][2][0] = 256; },
     "m.json: /luminance/rear_a/samples/2/0: an 8-bit level is an integer in [0, 255], got 256"},
    {"NegativeLuminance", [](json& d) { d["luminance"]["rear_a"]["samples"][1][1] = -2; },
     "m.json: /luminance/rear_a/samples/1/1: a luminance cannot be negative, got -2"},
    {"SampleNotAPair", [](json& d) { d["luminance"]["rear_a"]["samples"][0] = 7; },
     "m.json: /luminance/rear_a/samples/0: expected a pair [level, luminance], got a number 7"},
    {"Nothing", [](json& d) { d.erase("captures"), d.erase("luminance"); },
     "m.json: /: nothing to fit: the file has neither \"captures\" with markers nor \"luminance\""},
    {"UnknownPanel", [](json& d) { d["captures"][0]["markers"]["rear_c"] = d["captures"][0]["markers"]["rear_a"]; },
     "m.json: /captures/0/markers/rear_c: no panel named \"rear_c\" in " +
         testing::ExamplePath("paper_prototype.json") + "; did you mean \"rear_a\"?"},
    {"PixelOffThePanel",
     [](json& d) {
       d["captures"][0]["markers"]["rear_a"][1]["panel_pixel"] = {1280, 10};
     },
     "m.json: /captures/0/markers/rear_a/1/panel_pixel: (1280.0, 10.0) is off the panel's 1280 x 800 grid (columns "
     "and rows count from 0)"},
    {"AllDark",
     [](json& d) {
       d["luminance"]["rear_a"]["samples"] = {{0, 0}, {255, 0}};
     },
     "m.json: /luminance/rear_a/samples: every reading is zero: the panel's response cannot be fitted"},
};

INSTANTIATE_TEST_SUITE_P(Cases, BadMeasurementsTest, ::testing::ValuesIn(kBad),
                         [](const auto& test_info) { return test_info.param.name; });

TEST(MeasurementsTest, MalformedFileNamesTheFile) {
  const std::string path = ::testing::TempDir() + "/malformed_measurements.json";
  WriteFileAtomically(path, "{\"format\": \"layerlab-measurements/1\", \"captures\": [");
  try {
    ReadMeasurementsFile(path);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()).rfind(path + ":1:52: malformed JSON", 0), 0u) << e.what();
  }
}

TEST(MeasurementsTest, WrittenFileReadsBackTheSame) {
  const std::vector<testing::PanelTruth> truth = testing::ExampleTruth();
  const Measurements m =
      testing::SyntheticMeasurements(testing::BuiltSystem(Designed(), truth), truth, testing::ExampleSetup());
  const Measurements back = ParseMeasurements(json::parse(FormatMeasurements(m)), "back.json");
  ASSERT_EQ(back.marker_count(), m.marker_count());
  for (size_t c = 0; c < m.captures.size(); ++c)
    for (size_t p = 0; p < m.captures[c].panels.size(); ++p)
      for (size_t i = 0; i < m.captures[c].panels[p].markers.size(); ++i) {
        const MarkerObservation& a = m.captures[c].panels[p].markers[i];
        const MarkerObservation& b = MarkersOf(back, c, m.captures[c].panels[p].panel).markers[i];
        EXPECT_NEAR(a.angle_x, b.angle_x, 1e-7);  // camera pixels are written to 1e-4 px
        EXPECT_NEAR(a.angle_y, b.angle_y, 1e-7);
      }
  ASSERT_EQ(back.luminance_sample_count(), m.luminance_sample_count());
}

// A capture holding a panel twice (two photographs from one position) is written as two captures at that
// position, since "markers" is keyed by panel: both lists are read back, in order, none dropped.
TEST(MeasurementsTest, APanelTwiceInOneCaptureIsWrittenAsTwoCaptures) {
  Measurements m = ParseMeasurements(SmallValid(), "m.json");
  m.captures[0].camera_position = {2e-3, -1e-3};
  m.captures[0].panels[0].detection_noise = DetectionNoise{0.1 * testing::kArcmin, 40};
  PanelMarkers again = m.captures[0].panels[0];
  again.markers[0].camera_pixel = {1501.75, 1399.5};
  again.detection_noise = DetectionNoise{0.2 * testing::kArcmin, 40};
  PanelMarkers other = again;
  other.panel = "front_a";
  m.captures[0].panels = {m.captures[0].panels[0], other, again};
  const Measurements back = ParseMeasurements(json::parse(FormatMeasurements(m)), "back.json");
  ASSERT_EQ(back.captures.size(), 2u);
  EXPECT_EQ(back.marker_count(), 6u);
  for (const Capture& c : back.captures) {
    EXPECT_EQ(c.camera_position[0], 2e-3);
    EXPECT_EQ(c.camera_position[1], -1e-3);
  }
  ASSERT_EQ(back.captures[0].panels.size(), 2u);  // rear_a and front_a, then the second rear_a
  EXPECT_EQ((*MarkersOf(back, 0, "rear_a").markers[0].camera_pixel)[0], 1500.25);
  EXPECT_EQ((*MarkersOf(back, 1, "rear_a").markers[0].camera_pixel)[0], 1501.75);
  // Each list keeps its own photograph's detection noise.
  ASSERT_TRUE(MarkersOf(back, 0, "rear_a").detection_noise);
  ASSERT_TRUE(MarkersOf(back, 1, "rear_a").detection_noise);
  EXPECT_NEAR(MarkersOf(back, 0, "rear_a").detection_noise->sigma_rad, 0.1 * testing::kArcmin, 1e-12);
  EXPECT_NEAR(MarkersOf(back, 1, "rear_a").detection_noise->sigma_rad, 0.2 * testing::kArcmin, 1e-12);
}

// An example file is what its truth and setup produce, so that the true
// values its documentation states are the ones it was made from.
void ExpectExampleFileIs(const Measurements& m, const std::string& name) {
  const std::string path = testing::ExamplePath(name);
  if (std::getenv("LAYERLAB_REGENERATE_EXAMPLES")) WriteFileAtomically(path, FormatMeasurements(m));
  const Measurements file = ReadMeasurementsFile(path);
  ASSERT_EQ(file.captures.size(), m.captures.size());
  ASSERT_EQ(file.marker_count(), m.marker_count());
  for (size_t c = 0; c < m.captures.size(); ++c)
    for (size_t p = 0; p < m.captures[c].panels.size(); ++p)
      for (size_t i = 0; i < m.captures[c].panels[p].markers.size(); ++i) {
        const MarkerObservation& a = m.captures[c].panels[p].markers[i];
        const MarkerObservation& b = MarkersOf(file, c, m.captures[c].panels[p].panel).markers[i];
        ASSERT_EQ(a.col, b.col);
        ASSERT_EQ(a.row, b.row);
        ASSERT_NEAR((*a.camera_pixel)[0], (*b.camera_pixel)[0], 1e-3);
        ASSERT_NEAR((*a.camera_pixel)[1], (*b.camera_pixel)[1], 1e-3);
      }
  ASSERT_EQ(file.luminance.size(), m.luminance.size());
  for (size_t p = 0; p < m.luminance.size(); ++p)
    for (size_t i = 0; i < m.luminance[p].samples.size(); ++i)
      ASSERT_NEAR(LuminanceOf(file, m.luminance[p].panel).samples[i].luminance, m.luminance[p].samples[i].luminance,
                  1e-5 * m.luminance[p].samples[i].luminance + 1e-9);
}

TEST(ExampleMeasurements, IsMadeFromItsKnownTruth) {
  const std::vector<testing::PanelTruth> truth = testing::ExampleTruth();
  Measurements m =
      testing::SyntheticMeasurements(testing::BuiltSystem(Designed(), truth), truth, testing::ExampleSetup());
  m.description =
      "Synthetic measurements of examples/paper_prototype.json as built with known placements, "
      "0.3 arcmin marker noise and 0.3 % luminance noise; docs/measurements-format.md lists the true "
      "values.";
  ExpectExampleFileIs(m, kExample);
}

TEST(ExampleMeasurements, PerBranchIsMadeFromItsKnownTruth) {
  const DisplaySystem designed = Compile(LoadScene(testing::ExamplePath("per_branch_magnifiers.json")));
  const std::vector<testing::PanelTruth> truth = testing::PerBranchTruth();
  Measurements m = testing::SyntheticMeasurements(testing::BuiltSystem(designed, truth, testing::PerBranchOptics()),
                                                  truth, testing::PerBranchSetup());
  m.description =
      "Synthetic measurements of examples/per_branch_magnifiers.json as built with each branch's lens "
      "off its gap (lens_a +0.5 mm, lens_b -0.4 mm) and every panel moved, 0.3 arcmin marker noise; "
      "tests/calibration_test_util.cpp (PerBranchTruth) lists the true values.";
  ExpectExampleFileIs(m, "per_branch_magnifiers_measurements.json");
}

// The calibrated scene: the fitted values land in the scene file and come back
// through the ordinary loader and compiler, rotated and offset layers included.
TEST(CalibratedSceneTest, LoadsBackWithTheFittedValues) {
  const std::vector<testing::PanelTruth> truth = testing::ExampleTruth();
  const DisplaySystem built = testing::BuiltSystem(Designed(), truth);
  const Measurements m = testing::SyntheticMeasurements(built, truth, testing::ExampleSetup());
  CalibratedDisplay display;
  const CalibrationReport report = Calibrate(Designed(), m, CalibrationOptions{}, &display);
  ASSERT_TRUE(report.IsSolutionUsable()) << report.message;
  const std::string scene_path = testing::ExamplePath("paper_prototype.json");
  const nlohmann::ordered_json document = CalibratedSceneDocument(ReadDocumentInOrder(scene_path), scene_path, display);
  const DisplaySystem calibrated = testing::CompileJson(json::parse(document.dump()), "calibrated.json");
  ASSERT_EQ(calibrated.layers.size(), Designed().layers.size());
  for (const VirtualLayer& layer : calibrated.layers) {
    const CalibratedPanel* p = display.find(layer.name);
    ASSERT_NE(p, nullptr);
    EXPECT_NEAR(layer.panel_distance_m, p->distance_m, 1e-12) << layer.name;
    EXPECT_NEAR(layer.panel.eye_from_panel_m[0], p->eye_from_panel_x_m, 1e-14) << layer.name;
    EXPECT_NEAR(layer.panel.eye_from_panel_m[1], p->eye_from_panel_y_m, 1e-14) << layer.name;
    EXPECT_NEAR(layer.rotation_rad, p->rotation_rad, 1e-12) << layer.name;
    EXPECT_NEAR(layer.panel.gamma, p->gamma, 1e-10) << layer.name;
    EXPECT_NEAR(layer.panel.black_level, p->black_level, 1e-10) << layer.name;
  }
  EXPECT_NE(
      std::find(calibrated.components.begin(), calibrated.components.end(), "rotated layers (general projection path)"),
      calibrated.components.end());
  // Only calibrated keys changed: the panel's "virtual_depth" became its "distance", in its place.
  const auto& elements = document["elements"];
  EXPECT_EQ(elements[3]["name"], "front_a");
  EXPECT_EQ(std::next(elements[3].begin(), 2).key(), "distance");
  EXPECT_EQ(elements[3]["reversed"], true);
  EXPECT_EQ(elements[0], ReadDocumentInOrder(scene_path)["elements"][0]);
}

TEST(CalibratedSceneTest, RelativeTargetFollowsTheOutputFolder) {
  nlohmann::ordered_json scene = {{"solve", {{"target", "targets/lf"}}}};
  RebaseRelativePaths(scene, "examples/scene.json", "examples/out/calibrated.json");
  EXPECT_EQ(scene["solve"]["target"], "../targets/lf");
}

// Every path key follows, and bare file names (no parent folder) work: the
// cause of "cannot make absolute path" when fit ran inside examples/.
TEST(CalibratedSceneTest, EveryRelativePathFollowsFromBareFileNames) {
  nlohmann::ordered_json scene = {
      {"solve", {{"target_scene", "targets/dice.json"}}},
      {"run",
       {{"compare", {{"scenes", {"hybrid_pbs_hwp.json", "/abs/x.json"}}}}, {"contrast", {{"scenes", {"a.json"}}}}}}};
  RebaseRelativePaths(scene, "scene.json", "out/calibrated.json");
  EXPECT_EQ(scene["solve"]["target_scene"], "../targets/dice.json");
  EXPECT_EQ(scene["run"]["compare"]["scenes"][0], "../hybrid_pbs_hwp.json");
  EXPECT_EQ(scene["run"]["compare"]["scenes"][1], "/abs/x.json");
  EXPECT_EQ(scene["run"]["contrast"]["scenes"][0], "../a.json");
  RebaseRelativePaths(scene, "out/calibrated.json", "calibrated.json");
  EXPECT_EQ(scene["solve"]["target_scene"], "targets/dice.json");
}

// The files elements read beside the scene follow too: a lens's prescription, a panel's fixed pattern, a
// backlight's emission image and a world's scene.
TEST(CalibratedSceneTest, ElementFilesFollow) {
  nlohmann::ordered_json scene = {
      {"elements",
       {{{"type", "lens"}, {"prescription", "lenses/a.zmx"}},
        {{"type", "lc_panel"}, {"fixed_pattern", "mask.exr"}},
        {{"type", "backlight"}, {"pattern", {{"file", "glow.exr"}, {"pixel_pitch", "1 mm"}}}},
        {{"type", "world"}, {"scene", "/abs/wall.json"}}}}};
  RebaseRelativePaths(scene, "scene.json", "out/calibrated.json");
  EXPECT_EQ(scene["elements"][0]["prescription"], "../lenses/a.zmx");
  EXPECT_EQ(scene["elements"][1]["fixed_pattern"], "../mask.exr");
  EXPECT_EQ(scene["elements"][2]["pattern"]["file"], "../glow.exr");
  EXPECT_EQ(scene["elements"][3]["scene"], "/abs/wall.json");
}

}  // namespace
}  // namespace layerlab
