// TARGET.json: the examples parse into the geometry the light-field format
// documents, and bad targets are refused with file, pointer and reason, verbatim.
#include <cmath>
#include <functional>

#include "layerlab/framework/error.h"
#include "layerlab/framework/json_file.h"
#include "layerlab/targets/target_scene.h"
#include "layerlab/tests/render_test_util.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

using nlohmann::json;
using testing::Close;

TEST(TargetSceneTest, GratingExampleTakesItsFrustumFromThePaperPrototype) {
  TargetScene t = LoadTarget(testing::ExamplePath("targets/grating_1.3D.json"));
  const LightFieldGeometry& g = t.geometry;
  // The example window of docs/lightfield-format.md: the 35.5 x 18.2 deg frustum cut at 1.3 D.
  EXPECT_TRUE(Close(g.origin_z_m, 1 / 1.3, 1e-12));
  EXPECT_TRUE(Close(g.window_left_m, -0.24624, 0, 5e-6));
  EXPECT_TRUE(Close(g.window_top_m, 0.12312, 0, 5e-6));
  EXPECT_TRUE(Close(g.window_width_m, 0.49248, 0, 1e-5));
  EXPECT_TRUE(Close(g.window_height_m, 0.24624, 0, 1e-5));
  EXPECT_EQ(g.cols, 400);
  EXPECT_EQ(g.rows, 200);
  EXPECT_EQ(g.views_x, 13);
  EXPECT_EQ(g.views_y, 13);
  EXPECT_DOUBLE_EQ(g.eyebox_width_m, 6e-3);
  ASSERT_EQ(t.planes.size(), 1u);
  EXPECT_TRUE(Close(t.planes[0].depth_m, 1 / 1.3, 1e-12));
  EXPECT_EQ(t.samples_per_pixel, 1);
  EXPECT_NE(t.description.find("plane at 1.30 D (grating 2 cpd)"), std::string::npos) << t.description;
}

TEST(TargetSceneTest, DiceExamplePlacesItsMeshesInEyeSpace) {
  TargetScene t = LoadTarget(testing::ExamplePath("targets/dice.json"));
  ASSERT_EQ(t.meshes.size(), 2u);
  ASSERT_EQ(t.planes.size(), 1u);
  EXPECT_EQ(t.meshes[0].mesh.triangles.size(), 12u);
  // The die is 2 file units across, scaled by 4 cm, centered at (10 cm, 2 cm, 1 m).
  double sum[3] = {0, 0, 0};
  for (const auto& p : t.meshes[0].mesh.positions)
    for (int k = 0; k < 3; ++k) sum[k] += p[k] / 8;
  EXPECT_TRUE(Close(sum[0], 0.10, 0, 1e-12));
  EXPECT_TRUE(Close(sum[1], 0.02, 0, 1e-12));
  EXPECT_TRUE(Close(sum[2], 1.00, 0, 1e-12));
  EXPECT_TRUE(Close(t.meshes[0].uv_size_m, 0.08, 1e-12));
  EXPECT_EQ(t.samples_per_pixel, 4);
}

// One view of 8 x 8 pixels through a 10-degree window, with `objects`.
json OneViewTarget(std::vector<json> objects) {
  return {{"format", "layerlab-target/1"},
          {"light_field",
           {{"origin_plane", "1 D"},
            {"field_of_view", {"10 deg", "10 deg"}},
            {"resolution", {8, 8}},
            {"views", {1, 1}},
            {"eyebox", {"1 mm", "1 mm"}}}},
          {"objects", objects}};
}

TEST(TargetSceneTest, MeshPlacementIsScaleThenRotationXYZThenTranslation) {
  std::string dir = testing::ScratchDir();
  testing::WriteTextFile(dir + "/point.obj", "v 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\n");
  json target = OneViewTarget({{{"type", "mesh"},
                                {"file", "point.obj"},
                                {"scale", "1 cm"},
                                {"position", {0, 0, "2 D"}},
                                {"rotation", {"90 deg", "0 deg", "90 deg"}}}});
  TargetScene t = ParseTarget(target, dir + "/target.json");
  const auto& p = t.meshes[0].mesh.positions;
  // Rx(90) maps y to z and z to -y; then Rz(90) maps x to y and y to -x.
  auto expect = [&](int i, double x, double y, double z) {
    EXPECT_TRUE(Close(p[i][0], x, 0, 1e-15)) << i;
    EXPECT_TRUE(Close(p[i][1], y, 0, 1e-15)) << i;
    EXPECT_TRUE(Close(p[i][2], z, 0, 1e-15)) << i;
  };
  expect(0, 0, 0.01, 0.5);  // x -> x -> y
  expect(1, 0, 0, 0.51);    // y -> z -> z
  expect(2, 0.01, 0, 0.5);  // z -> -y -> x
}

// A moving die against the same die placed by hand: at a key's time the mesh is where a still scene with
// that key's placement puts it, halfway between two keys it is at the mean of their positions and angles,
// after the last key it holds, and a camera at c moves every vertex and plane by -c.
TEST(TargetSceneTest, KeysPlaceAMeshAsAStillSceneAtThatPlacement) {
  auto die = [](json position, json rotation) {
    return json{{"type", "mesh"},       {"file", "die.obj"},    {"scale", "2 cm"},
                {"position", position}, {"rotation", rotation}, {"color", 0.5}};
  };
  const json backdrop = {{"type", "plane"}, {"depth", "0.5 D"}, {"texture", {{"type", "constant"}, {"color", 0.2}}}};
  const std::string file = testing::ExamplePath("targets/target.json");
  auto scene = [&](json die_keys, json camera) {
    json moving = die({"1 cm", 0, "1 D"}, {"10 deg", 0, 0});
    if (!die_keys.is_null()) moving["keys"] = die_keys;
    json t = OneViewTarget({backdrop, moving});
    if (!camera.is_null()) t["animation"] = {{"frame_rate", "10 Hz"}, {"camera", camera}};
    return ParseTarget(t, file);
  };
  auto still = [&](json position, json rotation) {
    return ParseTarget(OneViewTarget({die(position, rotation)}), file).meshes[0].mesh.positions;
  };
  const json keys = {{{"time", "1 s"}, {"position", {"1 cm", 0, "1 m"}}, {"rotation", {"10 deg", "20 deg", 0}}},
                     {{"time", "3 s"}, {"position", {"5 cm", "-2 cm", "1.2 m"}}},
                     {{"time", "4 s"}, {"rotation", {"10 deg", "80 deg", "-30 deg"}}}};
  const TargetScene moving = scene(keys, nullptr);
  ASSERT_TRUE(moving.animation);
  EXPECT_EQ(moving.animation->frame_rate_hz, 30);
  auto expect_at = [&](double time_s, const std::vector<std::array<double, 3>>& expected, const char* what) {
    const TargetScene posed = TargetSceneAt(moving, time_s);
    ASSERT_EQ(posed.meshes[0].mesh.positions.size(), expected.size());
    for (size_t i = 0; i < expected.size(); ++i)
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(posed.meshes[0].mesh.positions[i][k], expected[i][k], 1e-15) << what << i;
    EXPECT_EQ(posed.time_s, time_s);
  };
  // Before the first key: the keys' first values (position and rotation both given at 1 s).
  expect_at(0.0, still({"1 cm", 0, "1 m"}, {"10 deg", "20 deg", 0}), "at 0 s ");
  // 2 s: position halfway from 1 s to 3 s; the rotation halfway from 1 s to 4 s is a third of the way.
  expect_at(2.0, still({"3 cm", "-1 cm", "1.1 m"}, {"10 deg", "40 deg", "-10 deg"}), "at 2 s ");
  expect_at(5.0, still({"5 cm", "-2 cm", "1.2 m"}, {"10 deg", "80 deg", "-30 deg"}), "after the keys ");

  const TargetScene seen = scene(nullptr, json{{{"time", "0 s"}, {"position", {0, 0, 0}}},
                                               {{"time", "2 s"}, {"position", {"2 cm", "-4 mm", "10 cm"}}}});
  const TargetScene at_1s = TargetSceneAt(seen, 1.0);
  const auto placed = still({"1 cm", 0, "1 D"}, {"10 deg", 0, 0});
  for (size_t i = 0; i < placed.size(); ++i) {
    EXPECT_NEAR(at_1s.meshes[0].mesh.positions[i][0], placed[i][0] - 0.01, 1e-15);
    EXPECT_NEAR(at_1s.meshes[0].mesh.positions[i][1], placed[i][1] + 0.002, 1e-15);
    EXPECT_NEAR(at_1s.meshes[0].mesh.positions[i][2], placed[i][2] - 0.05, 1e-15);
  }
  EXPECT_NEAR(at_1s.planes[0].depth_m, 2.0 - 0.05, 1e-15);
  EXPECT_NEAR(at_1s.planes[0].center_m[0], -0.01, 1e-15);
  EXPECT_NEAR(at_1s.planes[0].center_m[1], 0.002, 1e-15);

  // Read, a moving scene is posed at 0 s: a camera whose first key is 1 cm right sees everything 1 cm left,
  // and a plane whose size was left to cover every ray covers them from where it now is.
  const TargetScene shifted = scene(nullptr, json{{{"time", "0 s"}, {"position", {"1 cm", 0, 0}}}});
  EXPECT_EQ(shifted.time_s, 0.0);
  for (size_t i = 0; i < placed.size(); ++i)
    EXPECT_NEAR(shifted.meshes[0].mesh.positions[i][0], placed[i][0] - 0.01, 1e-15);
  EXPECT_NEAR(shifted.planes[0].center_m[0], -0.01, 1e-15);
  const std::array<double, 2> covering =
      CoveringSize(shifted.geometry, shifted.planes[0].depth_m, shifted.planes[0].center_m);
  EXPECT_EQ(shifted.planes[0].size_m, covering);
  EXPECT_GT(covering[0], CoveringSize(shifted.geometry, 2.0, {0, 0})[0]) << "the moved plane needs to be wider";

  // A still scene is the same at every time.
  const TargetScene unmoving = scene(nullptr, nullptr);
  EXPECT_FALSE(unmoving.animation);
  EXPECT_EQ(TargetSceneAt(unmoving, 3.0).meshes[0].mesh.positions, unmoving.meshes[0].mesh.positions);
  // A camera that walks through the plane is refused, naming the time.
  const TargetScene through =
      scene(nullptr, json{{{"time", "0 s"}, {"position", {0, 0, 0}}}, {{"time", "1 s"}, {"position", {0, 0, "3 m"}}}});
  try {
    TargetSceneAt(through, 0.8);
    FAIL() << "accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("at 0.8000 s, mesh die.obj: vertex"), std::string::npos) << e.what();
  }
}

json BaseTarget() {
  return {{"format", "layerlab-target/1"},
          {"light_field",
           {{"origin_plane", "1.3 D"},
            {"field_of_view", {"10 deg", "5 deg"}},
            {"resolution", {40, 20}},
            {"views", {3, 3}},
            {"eyebox", {"6 mm", "6 mm"}}}},
          {"objects",
           {{{"type", "plane"}, {"depth", "1.3 D"}, {"texture", {{"type", "grating"}, {"frequency", "2 cpd"}}}}}}};
}

struct BadTarget {
  std::string name;
  std::function<void(json&)> mutate;
  std::string message;  // after "<dir>/target.json: "
};

void PrintTo(const BadTarget& c, std::ostream* os) { *os << c.name; }

class BadTargetTest : public ::testing::TestWithParam<BadTarget> {};

TEST_P(BadTargetTest, IsRefusedWithItsLocation) {
  // Targets live in examples/targets/ so that "display" and mesh paths resolve.
  std::string file = testing::ExamplePath("targets/target.json");
  json target = BaseTarget();
  GetParam().mutate(target);
  try {
    ParseTarget(target, file);
    FAIL() << "accepted";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), file + ": " + GetParam().message);
  }
}

const BadTarget kBadTargets[] = {
    {"WrongFormat", [](json& t) { t["format"] = "layerlab-target/2"; },
     "/format: unknown target format \"layerlab-target/2\"; this layerlab reads \"layerlab-target/1\""},
    {"MisspelledTopKey", [](json& t) { t["sample_per_pixel"] = 4; },
     "/sample_per_pixel: unknown key \"sample_per_pixel\"; did you mean \"samples_per_pixel\"?"},
    {"NoWindow", [](json& t) { t["light_field"].erase("field_of_view"); },
     "/light_field: the light field needs its window: give \"field_of_view\", \"window\" or \"display\""},
    {"TwoWindows",
     [](json& t) {
       t["light_field"]["window"] = {{"left", 0}, {"top", 0}, {"width", 1}, {"height", 1}};
     },
     "/light_field/window: \"field_of_view\" already sets the window; give only one of \"field_of_view\", "
     "\"window\" and \"display\""},
    {"WindowOfNoWidth",  // the same reader and bounds as lightfield.json's window (framework/lightfield_io.h)
     [](json& t) {
       t["light_field"].erase("field_of_view");
       t["light_field"]["window"] = {{"left", "-1 m"}, {"top", "1 m"}, {"width", "0 m"}, {"height", "2 m"}};
     },
     "/light_field/window/width: must be in (0, 1000000] (SI units), got 0"},
    {"DisplayAndViews",
     [](json& t) {
       t["light_field"].erase("field_of_view");
       t["light_field"]["display"] = "../paper_prototype.json";
     },
     "/light_field/views: comes from the display (\"display\": \"../paper_prototype.json\"); remove it here"},
    {"MissingDisplay",
     [](json& t) {
       t["light_field"].erase("field_of_view");
       t["light_field"]["display"] = "../no_such_display.json";
     },
     "/light_field/display: no such scene file: " + testing::ExamplePath("targets/../no_such_display.json")},
    {"OriginAtInfinity", [](json& t) { t["light_field"]["origin_plane"] = "0 D"; },
     "/light_field/origin_plane: must be nearer than infinity (more than 0 D)"},
    {"FieldOfViewTooWide", [](json& t) { t["light_field"]["field_of_view"][0] = "190 deg"; },
     "/light_field/field_of_view/0: must be in (0, 3.141593) (SI units), got 3.316126"},
    {"MisspelledLightFieldKey", [](json& t) { t["light_field"]["eye_box"] = t["light_field"]["eyebox"]; },
     "/light_field/eye_box: unknown key \"eye_box\"; did you mean \"eyebox\"?"},
    {"TooManyRays",
     [](json& t) {
       t["light_field"]["resolution"] = {16384, 16384};
     },
     "/light_field: 2415919104 rays (views x pixels) is beyond the 2^31 this layerlab handles"},
    {"NoObjects", [](json& t) { t["objects"] = json::array(); },
     "/objects: no objects: the light field would show only the background"},
    {"ObjectTypeTypo", [](json& t) { t["objects"][0]["type"] = "plain"; },
     "/objects/0/type: \"plain\" is not one of plane or mesh; did you mean \"plane\"?"},
    {"BareDepth", [](json& t) { t["objects"][0]["depth"] = 0.77; },
     "/objects/0/depth: expected a depth with its unit, such as \"0.4 D\" or \"2.5 m\", got a number"},
    {"PlaneKeyTypo",
     [](json& t) {
       t["objects"][0]["centre"] = {0, 0};
     },
     "/objects/0/centre: unknown key \"centre\"; did you mean \"center\"?"},
    {"TextureKeyTypo", [](json& t) { t["objects"][0]["texture"]["frequncy"] = "1 cpd"; },
     "/objects/0/texture/frequncy: unknown key \"frequncy\"; did you mean \"frequency\"?"},
    {"BadBackground",
     [](json& t) {
       t["background"] = {0, 0};
     },
     "/background: expected one fraction or three [r, g, b], got 2 values"},
    {"ZeroLightDirection",
     [](json& t) {
       t["light"] = {{"direction_to_light", {0, 0, 0}}};
     },
     "/light/direction_to_light: must be a non-zero, finite direction"},
    {"MeshColorAndTexture",
     [](json& t) {
       t["objects"][0] = {{"type", "mesh"},  {"file", "die.obj"}, {"position", {0, 0, "1 D"}},
                          {"scale", "1 cm"}, {"color", 0.5},      {"texture", {{"type", "constant"}, {"color", 1}}}};
     },
     "/objects/0/texture: give \"color\" or \"texture\", not both"},
    {"MeshBehindTheEye",
     [](json& t) {
       t["objects"][0] = {{"type", "mesh"}, {"file", "die.obj"}, {"position", {0, 0, "5 cm"}}, {"scale", "10 cm"}};
     },
     "/objects/0/position: " + testing::ExamplePath("targets/die.obj") +
         ": vertex 0 lands at z = -0.0500 m, not in front of the pupil plane (z > 0)"},
    {"MeshPositionNotThree",
     [](json& t) {
       t["objects"][0] = {{"type", "mesh"}, {"file", "die.obj"}, {"position", {0, "1 D"}}};
     },
     "/objects/0/position: expected [x, y, z]: lengths, z also as a depth such as \"1 D\", got [0,\"1 D\"]"},
    {"KeysOutOfOrder",
     [](json& t) {
       t["objects"][0] = {
           {"type", "mesh"},
           {"file", "die.obj"},
           {"position", {0, 0, "1 D"}},
           {"scale", "1 cm"},
           {"keys", {{{"time", "1 s"}, {"rotation", {0, 0, 0}}}, {{"time", "0.5 s"}, {"rotation", {0, 0, 0}}}}}};
     },
     "/objects/0/keys/1/time: keys must come in increasing time; the key before is at 1.0000 s"},
    {"KeyOfNothing",
     [](json& t) {
       t["objects"][0] = {{"type", "mesh"},
                          {"file", "die.obj"},
                          {"position", {0, 0, "1 D"}},
                          {"scale", "1 cm"},
                          {"keys", {{{"time", "1 s"}}}}};
     },
     "/objects/0/keys/0: a key gives a \"position\", a \"rotation\" or both"},
    {"CameraKeyWithARotation",
     [](json& t) {
       t["animation"] = {{"camera", {{{"time", "0 s"}, {"rotation", {0, 0, 0}}}}}};
     },
     "/animation/camera/0/rotation: unknown key \"rotation\"; known keys: position, time"},
    {"PlaneKeys",
     [](json& t) {
       t["objects"][0]["keys"] = {{{"time", "0 s"}, {"position", {0, 0, "1 D"}}}};
     },
     "/objects/0/keys: unknown key \"keys\"; known keys: center, depth, size, texture, type"},
    {"NoFrameRate",
     [](json& t) {
       t["animation"] = {{"frame_rate", "0 Hz"}};
     },
     "/animation/frame_rate: must be in (0, 10000] (SI units), got 0"},
};

INSTANTIATE_TEST_SUITE_P(Targets, BadTargetTest, ::testing::ValuesIn(kBadTargets),
                         [](const auto& test) { return test.param.name; });

TEST(TargetSceneTest, TextureOnAMeshWithoutTextureCoordinatesIsRefused) {
  std::string dir = testing::ScratchDir();
  testing::WriteTextFile(dir + "/plain.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  json target = BaseTarget();
  target["objects"][0] = {{"type", "mesh"},
                          {"file", "plain.obj"},
                          {"position", {0, 0, "1 m"}},
                          {"texture", {{"type", "checkerboard"}, {"period", "1 cm"}}}};
  try {
    ParseTarget(target, dir + "/target.json");
    FAIL() << "accepted";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), dir + "/target.json: /objects/0/texture: " + dir +
                                         "/plain.obj has no texture coordinates (OBJ vt, PLY u v); give it a "
                                         "\"color\" instead");
  }
}

TEST(TargetSceneTest, MeshErrorsNameTheMeshFileAndLine) {
  std::string dir = testing::ScratchDir();
  testing::WriteTextFile(dir + "/broken.obj", "v 0 0 0\nv 1 0 0\nv 0 1 nan\nf 1 2 3\n");
  json target = BaseTarget();
  target["objects"][0] = {{"type", "mesh"}, {"file", "broken.obj"}, {"position", {0, 0, "1 m"}}};
  try {
    ParseTarget(target, dir + "/target.json");
    FAIL() << "accepted";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), dir + "/broken.obj:3: vertex coordinate \"nan\" is not a finite number");
  }
}

TEST(TargetSceneTest, DefaultPlaneCoversEveryRay) {
  LightFieldGeometry g;
  g.origin_z_m = 1.0;
  g.window_left_m = -0.1, g.window_top_m = 0.3, g.window_width_m = 0.4, g.window_height_m = 0.2;
  g.eyebox_width_m = 0.01, g.eyebox_height_m = 0.02;
  // At z = 2 rays reach x = v (1 - 2) + 2 x_lf: from -0.005 - 0.2 to 0.005 + 0.6.
  std::array<double, 2> size = CoveringSize(g, 2.0, {0, 0});
  EXPECT_TRUE(Close(size[0], 2 * 0.605 * 1.02, 1e-12));
  // y from -0.01 * -1 ... : v_y (1 - 2) + 2 y_lf, y_lf in [0.1, 0.3]: up to 0.01 + 0.6.
  EXPECT_TRUE(Close(size[1], 2 * 0.61 * 1.02, 1e-12));
}

}  // namespace
}  // namespace layerlab
