// A folded path's ghosts in the retinal images (systems/ghosts.h,
// analysis/retina_sweep.cpp): a panel behind two facing 90 % mirrors is seen
// straight through them and, fainter, once, twice, ... around the cavity
// between them. Full white on the panel, the retinal image's mean is the
// backlight times the sum of the route efficiencies (luminance-weighted),
// the main route's and every ghost's: each route images the whole panel over
// the small field looked at.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "layerlab/analysis/retina_sweep.h"
#include "test_util.h"

namespace layerlab {
namespace {

using layerlab::testing::CompileJson;

nlohmann::json Cavity() {
  nlohmann::json e = nlohmann::json::array();
  e.push_back({{"type", "eye"},
               {"name", "eye"},
               {"pupil_diameter", "3 mm"},
               {"pupil_samples", {3, 3}},
               {"eyebox", {"4 mm", "4 mm"}},
               {"views", {3, 3}},
               {"next", "m1"}});
  for (const char* name : {"m1", "m2"})
    e.push_back({{"type", "half_mirror"},
                 {"name", name},
                 {"fold", "back"},
                 {"reflectance", 0.9},
                 {"transmittance", 0.1},
                 {"gap", std::string(name) == "m1" ? "20 mm" : "5 mm"},
                 {"transmitted", std::string(name) == "m1" ? "m2" : "panel"}});
  e.push_back({{"type", "lc_panel"},
               {"name", "panel"},
               {"gap", "500 mm"},
               {"pixel_pitch", "1 mm"},
               {"resolution", {60, 40}},
               {"max_transmittance", 0.3},
               {"next", "backlight"}});
  e.push_back({{"type", "backlight"}, {"name", "backlight"}, {"luminance", "1000 cd/m2"}});
  return {{"format", "layerlab-scene/1"}, {"name", "cavity"}, {"elements", e}};
}

double Luminance(const Rgb& e) {
  return kLuminanceWeights[0] * e[0] + kLuminanceWeights[1] * e[1] + kLuminanceWeights[2] * e[2];
}

TEST(GhostRetina, TheRetinalImageAddsEveryGhost) {
  const DisplaySystem system = CompileJson(Cavity());
  ASSERT_GE(system.ghosts.size(), 3u);
  double main = Luminance(system.branches[0].efficiency), all = main;
  for (const Ghost& g : system.ghosts) all += Luminance(g.efficiency);
  ASSERT_GT(all, 2 * main);  // 0.81 + 0.81^2 + ... of the direct light

  const DisplayModel model(system, DisplayLightFieldGeometry(system), Sampling::kBilinear);
  const Patterns white = model.UniformPatterns(1.0f);
  const std::string folder = ::testing::TempDir() + "layerlab_ghost_retina";
  std::filesystem::remove_all(folder);
  RetinaSweepOptions o;
  o.states_diopters = {system.layers[0].diopters};
  o.resolution_deg = 0.25;
  o.field_x_deg = o.field_y_deg = 1.0;
  const std::vector<RetinaStateResult> r = WriteRetinaSweep(model, white, SceneRadiance{}, o, folder, nullptr);
  ASSERT_EQ(r.size(), 1u);
  EXPECT_NEAR(r[0].display_mean_cd_m2, 1000 * all, 1e-3 * 1000 * all);
}

}  // namespace
}  // namespace layerlab
