// The honest warnings (framework/warnings.h), each asserted by its text: a
// layer outside the eye's accommodation range, a target of another geometry
// than the display's, a contrast frequency above what the display can show,
// and a solve that ends far below what the display reaches, with its causes.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "layerlab/analysis/contrast.h"
#include "layerlab/solvers/objective.h"
#include "layerlab/systems/display_model.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

using testing::CompileJson;
using testing::ElementNamed;
using testing::ReadExample;

TEST(Warnings, ALayerOutsideTheEyesAccommodationRange) {
  EXPECT_TRUE(CompileJson(ReadExample("multiplicative_2layer.json")).warnings.empty());  // 0.4 and 2.2 D in [0, 2.6]
  nlohmann::json scene = ReadExample("multiplicative_2layer.json");
  ElementNamed(scene, "eye")["accommodation_range"] = {"0.5 D", "2 D"};
  const DisplaySystem s = CompileJson(scene);
  ASSERT_EQ(s.warnings.size(), 2u);
  EXPECT_EQ(s.warnings[0],
            "layer \"rear\" at 0.40 D lies outside the eye's accommodation range (0.50 to 2.00 D, the eye's "
            "accommodation_range): the eye cannot focus on it");
  EXPECT_EQ(s.warnings[1],
            "layer \"front\" at 2.20 D lies outside the eye's accommodation range (0.50 to 2.00 D, the eye's "
            "accommodation_range): the eye cannot focus on it");
}

TEST(Warnings, ATargetOfAnotherGeometryIsNamedPartByPart) {
  const DisplaySystem s = CompileJson(ReadExample("multiplicative_2layer.json"));
  LightFieldGeometry g = DisplayLightFieldGeometry(s);
  EXPECT_TRUE(TargetGeometryWarnings(s, g).empty());
  g.window_width_m *= 1.005;  // within 1 %: the same field
  EXPECT_TRUE(TargetGeometryWarnings(s, g).empty());
  g.views_x = g.views_y = 9;
  g.cols = 200;
  // Half the window at the origin plane: the field 2 atan(w / 4 z) instead of 2 atan(w / 2 z).
  const double z = g.origin_z_m, w = g.window_width_m;
  g.window_left_m /= 2, g.window_width_m /= 2;
  const double half_field = 2 * std::atan(w / 4 / z) * 180 / std::numbers::pi;
  const double fov_x = s.fov_x_rad * 180 / std::numbers::pi, fov_y = s.fov_y_rad * 180 / std::numbers::pi;
  const std::vector<std::string> warnings = TargetGeometryWarnings(s, g);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0],
            "the target light field's geometry differs from the display's: 9 x 9 views (the eye's: "
            "13 x 13), 200 x 200 pixels per view (the farthest layer's: 400 x 200), a field of " +
                FormatFixed(half_field, 2) + " x " + FormatFixed(fov_y, 2) +
                " deg (the display's: " + FormatFixed(fov_x, 2) + " x " + FormatFixed(fov_y, 2) +
                " deg); the layers are sampled at the target's rays (resampled)");
}

TEST(Warnings, AContrastFrequencyAboveWhatTheDisplayCanShow) {
  ContrastDisplay d;
  d.name = "two_layers";
  d.system = CompileJson(ReadExample("multiplicative_2layer.json"));
  // Nyquist of the finest layer: two of its pixels per cycle, its pixel's angle seen from the pupil.
  double finest = 0;
  for (const VirtualLayer& l : d.system.layers)
    finest = std::max(finest, 1 / (2 * std::atan(std::min(l.tan_pitch_x, l.tan_pitch_y)) * 180 / std::numbers::pi));
  EXPECT_NEAR(d.system.max_cpd, finest, 1e-9);
  ContrastOptions o;
  o.frequencies_cpd = {2, d.system.max_cpd, 6};
  const std::vector<std::string> warnings = ContrastWarnings({d}, o);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0], "two_layers: 6.00 cpd is above the " + FormatFixed(d.system.max_cpd, 2) +
                             " cpd the display can show (its finest layer's Nyquist frequency); the curve at 6.00 cpd "
                             "measures aliasing, not the display's contrast");
}

// A report that ended at `db` after one iteration on `model`'s rays, with
// `out_of_range` of its 3 x rays target values above the display's maximum.
SolverReport EndedAt(const DisplayModel& model, double db, size_t out_of_range) {
  SolverReport r;
  r.termination = Termination::kIterationLimit;
  r.iterations = 1;
  r.trace.push_back({1, 0.1, 1.0, db});
  r.final_psnr_db = db;
  r.rays = model.geometry().ray_count();
  r.out_of_range = out_of_range;
  return r;
}

TEST(Warnings, ASolveFarBelowWhatTheDisplayReachesSaysWhy) {
  nlohmann::json scene = testing::ShrunkExample("additive_2layer.json", 8, 6, 3);
  const DisplaySystem even = CompileJson(scene);
  const DisplayModel even_model(even, DisplayLightFieldGeometry(even));
  EXPECT_FALSE(FarBelowWarning(even_model, EndedAt(even_model, kFarBelowPsnrDb, 1000)));  // at the line: not below
  EXPECT_EQ(*FarBelowWarning(even_model, EndedAt(even_model, 17.5, 12)),
            "the solve ended at 17.50 dB, far below what the display can reach (under 18 dB: 10 dB below the lowest "
            "shipped display on the dice); no cause found in the target's range or the branches' brightness (1 "
            "iteration: more may help)");

  ElementNamed(scene, "half_mirror")["reflectance"] = 0.1;
  ElementNamed(scene, "half_mirror")["transmittance"] = 0.9;
  const DisplaySystem uneven = CompileJson(scene);
  const DisplayModel model(uneven, DisplayLightFieldGeometry(uneven));
  std::string dim, bright;
  for (const Branch& b : uneven.branches) (b.name.find("reflected") != std::string::npos ? dim : bright) = b.name;
  // The same panels and backlights behind both ports: the branches' light is 0.1 : 0.9.
  EXPECT_EQ(*FarBelowWarning(model, EndedAt(model, 9.25, 3 * model.geometry().ray_count() / 8)),
            "the solve ended at 9.25 dB, far below what the display can reach (under 18 dB: 10 dB below the lowest "
            "shipped display on the dice); 12.5 % of the target's values are above what the display can show (they "
            "were clipped); unequal branch brightness: branch \"" +
                dim + "\" gives 11.1 % of the light of \"" + bright + "\"");
}

}  // namespace
}  // namespace layerlab
