// Optical see-through (elements/world.cpp, systems/world_view.h): a world
// reached through a combiner's port is seen with the path's efficiency for
// natural light, added at the eye to the display's light. Checked by hand:
// a half mirror passes its transmittance; a polarizing beam splitter passes
// natural light (Tp + Ts) / 2 whatever a half-wave plate does before it;
// the ambient contrast ratio is (peak + world) / world from the backlight,
// the mirror and the panels; the retinal images with the world are the
// display's plus the world's luminance over the display's white.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <utility>

#include "layerlab/analysis/retina_sweep.h"
#include "layerlab/analysis/world_scene.h"
#include "layerlab/framework/exr_image.h"
#include "layerlab/solvers/objective.h"
#include "layerlab/solvers/solver.h"
#include "layerlab/systems/system_report.h"
#include "layerlab/systems/world_view.h"
#include "test_util.h"

namespace layerlab {
namespace {

using layerlab::testing::CompileError;
using layerlab::testing::CompileJson;

// An eye, a combiner 15 mm away reflecting a magnifier and two panels (0.3 each) over a 5000 cd/m2
// backlight, transmitting `world` (the element "outside", 300 cd/m2).
nlohmann::json SeeThrough(const nlohmann::json& combiner, const nlohmann::json& world_path = nullptr) {
  nlohmann::json s = {{"format", "layerlab-scene/1"}, {"name", "see-through test"}};
  nlohmann::json e = nlohmann::json::array();
  e.push_back({{"type", "eye"},
               {"name", "eye"},
               {"pupil_diameter", "4 mm"},
               {"pupil_samples", {3, 3}},
               {"eyebox", {"4 mm", "4 mm"}},
               {"views", {3, 3}},
               {"next", "combiner"}});
  nlohmann::json c = combiner;
  c["name"] = "combiner", c["gap"] = "15 mm", c["reflected"] = "lens";
  c["transmitted"] = world_path.is_null() ? "outside" : world_path["name"];
  e.push_back(c);
  if (!world_path.is_null()) {
    nlohmann::json w = world_path;
    w["next"] = "outside";
    e.push_back(w);
  }
  e.push_back(
      {{"type", "thin_lens"}, {"name", "lens"}, {"focal_length", "50 mm"}, {"gap", "10 mm"}, {"next", "front"}});
  for (const char* panel : {"front", "rear"})
    e.push_back({{"type", "lc_panel"},
                 {"name", panel},
                 {"virtual_depth", std::string(panel) == "front" ? "2 D" : "0.5 D"},
                 {"pixel_pitch", "100 um"},
                 {"resolution", {40, 30}},
                 {"next", std::string(panel) == "front" ? "rear" : "light"}});
  e.push_back({{"type", "backlight"}, {"name", "light"}, {"luminance", "5000 cd/m2"}});
  e.push_back({{"type", "world"}, {"name", "outside"}, {"luminance", "300 cd/m2"}});
  s["elements"] = e;
  return s;
}

TEST(SeeThrough, AHalfMirrorShowsTheWorldAtItsTransmittance) {
  const DisplaySystem system =
      CompileJson(SeeThrough({{"type", "half_mirror"}, {"reflectance", 0.3}, {"transmittance", 0.7}}));
  ASSERT_EQ(system.worlds.size(), 1u);
  const WorldView& w = system.worlds[0];
  EXPECT_EQ(w.element, "outside");
  EXPECT_EQ(w.name, "combiner.transmitted");
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(w.efficiency[c], 0.7, 1e-15);
  EXPECT_NEAR(LuminanceOf(WorldAtEye(system)), 210, 1e-12);
  // The display's full white: 5000 cd/m2 x 0.3 (mirror) x 0.3 x 0.3 (the panels) = 135 cd/m2.
  const double peak = 5000 * 0.3 * 0.3 * 0.3;
  EXPECT_NEAR(LuminanceOf(system.peak_luminance_cd_m2), peak, 1e-9);
  EXPECT_NEAR(AmbientContrastRatio(system), (peak + 210) / 210, 1e-12);
  const std::string table = FormatSystemTable(system);
  EXPECT_NE(table.find("world \"outside\"        through combiner.transmitted 300.0 cd/m2 x efficiency 0.7000 "
                       "0.7000 0.7000 = 210.00 210.00 210.00 cd/m2 at the eye"),
            std::string::npos)
      << table;
  EXPECT_NE(table.find("ambient contrast       1.643: the display's full white over the world, (135.00 + 210.00) / "
                       "210.00 cd/m2"),
            std::string::npos)
      << table;
  EXPECT_EQ(SystemToJson(system)["worlds"][0]["path"], "combiner.transmitted");
}

// Natural light through a polarizing beam splitter: half of it along p (Tp), half along s (Ts), whatever a
// half-wave plate turns before; one linear polarization alone would give Tp or Ts.
TEST(SeeThrough, NaturalLightThroughAPolarizingSplitterIsTheMeanOfTwoPolarizations) {
  const nlohmann::json pbs = {
      {"type", "pbs"}, {"transmittance_p", 0.9}, {"transmittance_s", 0.02}, {"reflectance_s", 0.98}};
  const nlohmann::json hwp = {{"type", "hwp"}, {"name", "plate"}, {"fast_axis", "22.5 deg"}};
  for (const nlohmann::json& path : {nlohmann::json(nullptr), hwp}) {
    const DisplaySystem system = CompileJson(SeeThrough(pbs, path));
    ASSERT_EQ(system.worlds.size(), 1u);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(system.worlds[0].efficiency[c], 0.5 * (0.9 + 0.02), 1e-12);
  }
  // A polarizer along p before the splitter: natural light leaves it at half along p, which the splitter passes
  // at Tp; across p, at Ts.
  for (const double deg : {0.0, 90.0}) {
    const nlohmann::json polarizer = {
        {"type", "linear_polarizer"}, {"name", "sheet"}, {"axis", std::to_string(deg) + " deg"}};
    const DisplaySystem system = CompileJson(SeeThrough(pbs, polarizer));
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(system.worlds[0].efficiency[c], 0.5 * (deg == 0 ? 0.9 : 0.02), 1e-12);
  }
}

TEST(SeeThrough, AWorldWithoutACombinerOrADisplayIsRefused) {
  nlohmann::json inline_world = SeeThrough({{"type", "half_mirror"}});
  inline_world["elements"][0]["next"] = "outside";
  EXPECT_NE(CompileError(inline_world).find("the world \"outside\" is reached without a combiner"), std::string::npos)
      << CompileError(inline_world);
  nlohmann::json only_worlds = SeeThrough({{"type", "half_mirror"}});
  only_worlds["elements"][1]["reflected"] = "far";
  only_worlds["elements"].push_back({{"type", "world"}, {"name", "far"}, {"luminance", "10 cd/m2"}});
  const std::string e = CompileError(only_worlds);
  EXPECT_TRUE(e.find("no panel lies on any path from the eye") != std::string::npos ||
              e.find("is not on the optical path from the eye") != std::string::npos)
      << e;
}

// The retinal images with the world are the display's plus the world's luminance at the eye over the
// display's white, and retina.csv gives (display mean + world) / world.
TEST(SeeThrough, TheRetinalImagesAddTheWorld) {
  const DisplaySystem system =
      CompileJson(SeeThrough({{"type", "half_mirror"}, {"reflectance", 0.3}, {"transmittance", 0.7}}));
  const DisplayModel model(system, DisplayLightFieldGeometry(system), Sampling::kBilinear);
  Patterns t = InitialPatterns(model, SolverOptions{});
  for (LayerPattern& p : t)
    for (size_t k = 0; k < p.rgb.size(); ++k) p.rgb[k] = 0.2f + 0.6f * float(k % 7) / 7;
  const std::string folder = ::testing::TempDir() + "layerlab_see_through";
  std::filesystem::remove_all(folder);
  RetinaSweepOptions o;
  o.states_diopters = {1.0};
  o.resolution_deg = 0.5;
  o.exr_pixels = ExrPixels::kFloat;
  const std::vector<RetinaStateResult> r = WriteRetinaSweep(model, t, SceneRadiance{}, o, folder, nullptr);
  const Image display = ReadExr(folder + "/display/1.00D.exr", {"R", "G", "B"});
  const Image seen = ReadExr(folder + "/see_through/1.00D.exr", {"R", "G", "B"});
  ASSERT_EQ(seen.pixels.size(), display.pixels.size());
  const double world = 210 / model.white_luminance();
  for (size_t i = 0; i < seen.pixels.size(); ++i) ASSERT_NEAR(seen.pixels[i], display.pixels[i] + world, 1e-6);
  ASSERT_EQ(r.size(), 1u);
  EXPECT_NEAR(r[0].world_cd_m2, 210, 1e-9);
  EXPECT_NEAR(r[0].contrast_against_world, (r[0].display_mean_cd_m2 + 210) / 210, 1e-12);
  std::ifstream csv(folder + "/retina.csv");
  std::string header;
  std::getline(csv, header);
  EXPECT_NE(header.find(",world_cd_m2,contrast_against_world"), std::string::npos) << header;
}

// A world with a scene: a plane of constant radiance 0.5 is seen as 0.5 x 210 cd/m2 wherever it is.
TEST(SeeThrough, AWorldsSceneIsTracedIntoTheImages) {
  const std::string folder = ::testing::TempDir() + "layerlab_see_through_scene";
  std::filesystem::remove_all(folder);
  std::filesystem::create_directories(folder);
  nlohmann::json wall = {{"format", "layerlab-target/1"},
                         {"light_field",
                          {{"origin_plane", "0.5 D"},
                           {"field_of_view", {"40 deg", "30 deg"}},
                           {"resolution", {8, 6}},
                           {"views", {1, 1}},
                           {"eyebox", {"1 mm", "1 mm"}}}},
                         {"objects",
                          {{{"type", "plane"},
                            {"depth", "0.5 D"},
                            {"size", {"80 deg", "60 deg"}},
                            {"texture", {{"type", "constant"}, {"color", 0.5}}}}}}};
  std::ofstream(folder + "/wall.json") << wall.dump();
  nlohmann::json scene = SeeThrough({{"type", "half_mirror"}, {"reflectance", 0.3}, {"transmittance", 0.7}});
  scene["elements"].back()["scene"] = "wall.json";
  const DisplaySystem system = CompileJson(scene, folder + "/scene.json");
  ASSERT_EQ(system.worlds.size(), 1u);
  EXPECT_EQ(system.worlds[0].scene_file, folder + "/wall.json");
  const DisplayModel model(system, DisplayLightFieldGeometry(system), Sampling::kBilinear);
  const Patterns t = InitialPatterns(model, SolverOptions{});
  RetinaSweepOptions o;
  o.states_diopters = {1.0};
  o.resolution_deg = 0.5;
  o.exr_pixels = ExrPixels::kFloat;
  o.world = WorldSceneRadiance(system);
  ASSERT_TRUE(o.world);
  const std::vector<RetinaStateResult> r = WriteRetinaSweep(model, t, SceneRadiance{}, o, folder + "/out", nullptr);
  const Image display = ReadExr(folder + "/out/display/1.00D.exr", {"R", "G", "B"});
  const Image seen = ReadExr(folder + "/out/see_through/1.00D.exr", {"R", "G", "B"});
  const double world = 0.5 * 210 / model.white_luminance();
  for (size_t i = 0; i < seen.pixels.size(); ++i) ASSERT_NEAR(seen.pixels[i], display.pixels[i] + world, 1e-6);
  EXPECT_NEAR(r[0].world_cd_m2, 105, 1e-4);
  // A patch 11 deg to the right of the world is seen on the right through the transmitted port, and on the
  // left through the reflected one, which mirrors it.
  nlohmann::json patch = wall;
  patch["objects"][0]["size"] = {"0.1 m", "0.1 m"};
  patch["objects"][0]["center"] = {"0.4 m", "0 m"};  // at 2 m: 11.3 deg right
  std::ofstream(folder + "/patch.json") << patch.dump();
  for (const bool reflected : {false, true}) {
    nlohmann::json s = scene;
    s["elements"].back()["scene"] = "patch.json";
    if (reflected) std::swap(s["elements"][1]["reflected"], s["elements"][1]["transmitted"]);
    const DisplaySystem mirrored = CompileJson(s, folder + "/scene.json");
    const SceneRadiance radiance = WorldSceneRadiance(mirrored);
    double left = 0, right = 0;
    const PupilPoint centre{};
    for (int k = -20; k <= 20; ++k) {
      const double tan = std::tan(k * 1.0 * std::numbers::pi / 180);
      (k < 0 ? left : right) += radiance(centre, tan, 0)[1];
    }
    EXPECT_GT(reflected ? left : right, 0) << (reflected ? "reflected" : "transmitted");
    EXPECT_EQ(reflected ? right : left, 0) << (reflected ? "reflected" : "transmitted");
  }
  // Through a lens the scene would be imaged: refused.
  nlohmann::json imaged = scene;
  imaged["elements"][1]["transmitted"] = "glass";
  imaged["elements"].push_back(
      {{"type", "thin_lens"}, {"name", "glass"}, {"focal_length", "1 m"}, {"gap", "5 mm"}, {"next", "outside"}});
  const std::string e = testing::ErrorOf([&] { CompileJson(imaged, folder + "/scene.json"); });
  EXPECT_NE(e.find("the world \"outside\" is seen through \"glass\", which has optical power"), std::string::npos) << e;
}

}  // namespace
}  // namespace layerlab
