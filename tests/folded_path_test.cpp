// Paths that pass an element more than once (systems/compile.cpp, Walk and
// WalkBack; docs/optics.md): a pancake lens and a birdbath described as
// built. Checked against a hand-unfolded computation written here: each
// route's Jones matrices multiplied in the order light meets them (plain 2x2
// complex matrices, not layerlab's), and its depths by the thin-lens ABCD
// matrices of the unfolded path lengths.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <complex>
#include <numbers>
#include <string>

#include "layerlab/elements/registry.h"
#include "layerlab/elements/splitter_ports.h"
#include "layerlab/systems/ghosts.h"
#include "layerlab/systems/route_light.h"
#include "test_util.h"

namespace layerlab {
namespace {

using layerlab::testing::CompileError;
using layerlab::testing::CompileJson;
using Matrix = Eigen::Matrix2cd;
using Vector = Eigen::Vector2cd;

constexpr double kPi = std::numbers::pi;
const std::array<double, 3> kWavelengths = {612e-9, 549e-9, 465e-9};  // the eye's channels (the default)

nlohmann::json Eye(const std::string& next) {
  return {{"type", "eye"},
          {"name", "eye"},
          {"pupil_diameter", "4 mm"},
          {"pupil_samples", {3, 3}},
          {"eyebox", {"4 mm", "4 mm"}},
          {"views", {3, 3}},
          {"next", next}};
}

nlohmann::json Panel(const std::string& name, const std::string& depth, const std::string& next) {
  return {{"type", "lc_panel"},
          {"name", name},
          {"virtual_depth", depth},
          {"pixel_pitch", "80 um"},
          {"resolution", {40, 30}},
          {"max_transmittance", 0.3},
          {"next", next}};
}

// The pancake of examples/pancake.json, from the eye: a reflective polarizer at 12 mm passing y (leaking
// `leak` of x), a quarter-wave plate at -45 deg (1 mm on), the concave half mirror of focal length 20.5 mm
// (7 mm on), a quarter-wave plate at 45 deg (1 mm), a polarizer along x (0.5 mm), then two panels.
nlohmann::json Pancake(double leak) {
  nlohmann::json e = nlohmann::json::array();
  e.push_back(Eye("rp"));
  e.push_back({{"type", "pbs"},
               {"name", "rp"},
               {"fold", "back"},
               {"p_axis", "90 deg"},
               {"transmittance_s", leak},
               {"reflectance_s", 1 - leak},
               {"gap", "12 mm"},
               {"transmitted", "qa"}});
  e.push_back({{"type", "qwp"},
               {"name", "qa"},
               {"fast_axis", "-45 deg"},
               {"design_wavelength", "549 nm"},
               {"gap", "1 mm"},
               {"next", "hm"}});
  e.push_back({{"type", "half_mirror"},
               {"name", "hm"},
               {"fold", "back"},
               {"focal_length", "20.5 mm"},
               {"gap", "7 mm"},
               {"transmitted", "qb"}});
  e.push_back({{"type", "qwp"},
               {"name", "qb"},
               {"fast_axis", "45 deg"},
               {"design_wavelength", "549 nm"},
               {"gap", "1 mm"},
               {"next", "lp"}});
  e.push_back({{"type", "linear_polarizer"}, {"name", "lp"}, {"axis", "0 deg"}, {"gap", "0.5 mm"}, {"next", "front"}});
  e.push_back(Panel("front", "1.6 D", "rear"));
  e.push_back(Panel("rear", "0.4 D", "backlight"));
  e.push_back({{"type", "backlight"}, {"name", "backlight"}, {"luminance", "5000 cd/m2"}});
  return {{"format", "layerlab-scene/1"}, {"name", "pancake"}, {"elements", e}};
}

// Hand Jones matrices in eye-space x, y.
Matrix Rotation(double a) {
  Matrix r;
  r << std::cos(a), -std::sin(a), std::sin(a), std::cos(a);
  return r;
}
Matrix Retarder(double delta, double axis) {
  Matrix d;
  d << 1, 0, 0, std::polar(1.0, delta);
  return Rotation(axis) * d * Rotation(-axis);
}
Matrix Diagonal(double x, double y) {
  Matrix d;
  d << std::sqrt(x), 0, 0, std::sqrt(y);
  return d;
}

// The fraction of the panels' x-polarized light that one pancake route brings to the eye in channel c:
// `round_trips` times back and forth between the half mirror and the polarizer before leaving through it.
double PancakeRoute(int c, int round_trips, double leak) {
  const double delta = 2 * kPi * 0.25 * 549e-9 / kWavelengths[c];  // a zero-order quarter-wave plate
  const Matrix qa = Retarder(delta, -kPi / 4), qb = Retarder(delta, kPi / 4);
  const Matrix through = Diagonal(leak, 1), back = Diagonal(1 - leak, 0);  // the polarizer's p axis is y
  const Matrix half = Matrix::Identity() * std::sqrt(0.5);
  Vector e(1, 0);     // the panels' light, polarized along x
  e = half * qb * e;  // through the polarizer (x), the panel-side plate and the half mirror
  for (int k = 0; k < round_trips; ++k) e = half * qa * back * qa * e;  // back to the polarizer and forth
  e = through * qa * e;  // out through the eye-side plate and the polarizer
  return e.squaredNorm();
}

// What the eye sees of a panel beyond thin powers: D = A / B of the unfolded ABCD matrix, the gaps and
// powers listed from the pupil outward.
double Diopters(const std::vector<std::pair<double, double>>& gap_then_power) {
  Eigen::Matrix2d m = Eigen::Matrix2d::Identity();
  for (const auto& [gap, power] : gap_then_power) {
    Eigen::Matrix2d t, l;
    t << 1, gap, 0, 1;
    l << 1, 0, -power, 1;
    m = l * t * m;
  }
  return m(0, 0) / m(0, 1);
}

const Ghost* GhostBy(const DisplaySystem& s, const std::string& route) {
  for (const Ghost& g : s.ghosts)
    if (g.name == route) return &g;
  return nullptr;
}

TEST(FoldedPath, PancakeEfficienciesAreTheHandUnfoldedJonesCalculus) {
  const double leak = 0.01;
  const DisplaySystem s = CompileJson(Pancake(leak));
  ASSERT_EQ(s.branches.size(), 1u);
  const Branch& b = s.branches[0];
  EXPECT_EQ(b.name, "rp.transmitted/hm.reflected/rp.reflected/hm.transmitted");
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(b.optics_efficiency[c], PancakeRoute(c, 1, leak), 1e-12) << c;
  EXPECT_NEAR(b.optics_efficiency[1], 0.25 * (1 - leak), 1e-12);  // green: a quarter at best

  // Straight through the half mirror: the polarizer's leak; twice around the fold: the plates' error.
  const Ghost* direct = GhostBy(s, "rp.transmitted/hm.transmitted");
  const Ghost* twice = GhostBy(s, "rp.transmitted/hm.reflected/rp.reflected/hm.reflected/rp.reflected/hm.transmitted");
  ASSERT_NE(direct, nullptr);
  ASSERT_NE(twice, nullptr);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(direct->optics_efficiency[c], PancakeRoute(c, 0, leak), 1e-12) << c;
    EXPECT_NEAR(twice->optics_efficiency[c], PancakeRoute(c, 2, leak), 1e-12) << c;
    EXPECT_NEAR(direct->efficiency[c], direct->optics_efficiency[c] * 0.09, 1e-12) << c;
  }
  EXPECT_NEAR(direct->optics_efficiency[1], 0.5 * leak, 1e-12);              // the plates cancel: x meets the polarizer
  EXPECT_GT(twice->optics_efficiency[2], 10 * twice->optics_efficiency[1]);  // blue leaks most
  for (const Ghost& g : s.ghosts) EXPECT_EQ(g.branch, 0);
}

TEST(FoldedPath, PancakeGhostDepthsAreTheUnfoldedPaths) {
  const DisplaySystem s = CompileJson(Pancake(0.01));
  const double f = 20.5e-3, P = 1 / f;
  const Branch& b = s.branches[0];
  const std::string direct = "rp.transmitted/hm.transmitted",
                    twice = "rp.transmitted/hm.reflected/rp.reflected/hm.reflected/rp.reflected/hm.transmitted";
  for (size_t k = 0; k < b.layers.size(); ++k) {
    const VirtualLayer& main = s.layers[b.layers[k]];
    // On the main route the polarizer is 20 + 8 + 8 + 1.5 mm from the pupil; the panel t beyond it.
    const double t = main.position_m - 37.5e-3;
    EXPECT_NEAR(main.diopters, Diopters({{20e-3, P}, {17.5e-3 + t, 0}}), 1e-9) << k;
    const VirtualLayer& d = GhostBy(s, direct)->layers[k];
    EXPECT_NEAR(d.position_m, 21.5e-3 + t, 1e-15);
    EXPECT_NEAR(d.diopters, 1 / (21.5e-3 + t), 1e-9);  // nothing with power: the panel where it is
    const VirtualLayer& w = GhostBy(s, twice)->layers[k];
    EXPECT_NEAR(w.position_m, 53.5e-3 + t, 1e-15);
    EXPECT_NEAR(w.diopters, Diopters({{20e-3, P}, {16e-3, P}, {17.5e-3 + t, 0}}), 1e-9) << k;
    EXPECT_EQ(w.element, main.element);
  }
  // The main route's front panel: the gap that images it at 1.6 D, by the magnifier formula.
  const double d1 = 20e-3, D = 1.6;
  const double d2 = (D * d1 - 1) / (D * P * d1 - P - D);  // A / B = D with A = 1 - P d2, B = d1 + d2 - P d1 d2
  EXPECT_NEAR(s.layers[b.layers[0]].position_m, d1 + d2, 1e-12);
}

// The birdbath of examples/birdbath.json: a splitter passed twice, once each way.
nlohmann::json Birdbath() {
  nlohmann::json e = nlohmann::json::array();
  e.push_back(Eye("splitter"));
  e.push_back({{"type", "half_mirror"},
               {"name", "splitter"},
               {"fold", "vertical"},
               {"gap", "20 mm"},
               {"transmitted", "bath"},
               {"reflected", nullptr},
               {"reflected_from_behind", "front"}});
  e.push_back({{"type", "half_mirror"},
               {"name", "bath"},
               {"fold", "back"},
               {"focal_length", "40 mm"},
               {"gap", "25 mm"},
               {"transmitted", "outside"}});
  e.push_back(Panel("front", "2 D", "rear"));
  e.push_back(Panel("rear", "0.6 D", "backlight"));
  e.push_back({{"type", "backlight"}, {"name", "backlight"}, {"luminance", "10000 cd/m2"}});
  e.push_back({{"type", "world"}, {"name", "outside"}, {"luminance", "300 cd/m2"}});
  return {{"format", "layerlab-scene/1"}, {"name", "birdbath"}, {"elements", e}};
}

TEST(FoldedPath, BirdbathPassesItsSplitterTwice) {
  const DisplaySystem s = CompileJson(Birdbath());
  ASSERT_EQ(s.branches.size(), 1u);
  const Branch& b = s.branches[0];
  EXPECT_EQ(b.name, "splitter.transmitted/bath.reflected/splitter.reflected");
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(b.optics_efficiency[c], 0.125, 1e-15);  // reflected, reflected, transmitted: 0.5 each
    EXPECT_NEAR(b.efficiency[c], 0.125 * 0.09, 1e-15);
  }
  EXPECT_TRUE(s.ghosts.empty());  // every other route ends in the eye or the light trap
  ASSERT_EQ(s.worlds.size(), 1u);
  EXPECT_EQ(s.worlds[0].name, "splitter.transmitted/bath.transmitted");
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(s.worlds[0].efficiency[c], 0.25, 1e-15);
  // Unfolded: 45 mm to the bath (P = 1 / 40 mm), then 25 mm back to the splitter and d beyond it.
  const double P = 1 / 40e-3, d1 = 45e-3;
  for (int k : b.layers) {
    const VirtualLayer& l = s.layers[k];
    const double d2 = l.position_m - d1;
    EXPECT_NEAR(l.diopters, Diopters({{d1, P}, {d2, 0}}), 1e-9);
    EXPECT_TRUE(l.flip_x);  // the bath at normal incidence mirrors left-right, the splitter's fold top-bottom
    EXPECT_TRUE(l.flip_y);
  }
  const double D = 2.0, d2 = (D * d1 - 1) / (D * P * d1 - P - D);
  EXPECT_NEAR(s.layers[b.layers[0]].position_m, d1 + d2, 1e-12);
}

TEST(FoldedPath, GhostsShowTheirBranchsPatterns) {
  const DisplaySystem s = CompileJson(Pancake(0.01));
  const GhostedDisplay g = WithGhosts(s);
  ASSERT_EQ(g.system.layers.size(), s.layers.size() * (1 + s.ghosts.size()));
  ASSERT_EQ(g.system.branches.size(), 1 + s.ghosts.size());
  EXPECT_TRUE(g.system.ghosts.empty());
  for (size_t k = 0; k < g.system.layers.size(); ++k) {
    EXPECT_EQ(g.system.layers[k].element, s.layers[g.pattern_of[k]].element) << k;
    if (k > 0) {
      EXPECT_LE(g.system.layers[k - 1].diopters, g.system.layers[k].diopters);  // farthest first
    }
  }
  for (size_t n = 0; n < s.ghosts.size(); ++n) {
    const Branch& b = g.system.branches[1 + n];
    EXPECT_EQ(b.name, s.ghosts[n].name);
    for (int c = 0; c < 3; ++c) EXPECT_EQ(b.efficiency[c], s.ghosts[n].efficiency[c]);
    for (size_t k = 0; k < b.layers.size(); ++k)
      EXPECT_DOUBLE_EQ(g.system.layers[b.layers[k]].diopters, s.ghosts[n].layers[k].diopters);
  }
  Patterns shown;
  for (size_t k = 0; k < s.layers.size(); ++k) shown.emplace_back(1, 1, static_cast<float>(k + 1));
  const Patterns seen = GhostedPatterns(g, shown);
  for (size_t k = 0; k < seen.size(); ++k) EXPECT_EQ(seen[k].rgb[0], static_cast<float>(g.pattern_of[k] + 1));
  // Without a folded path: the display itself.
  const DisplaySystem plain = CompileJson(layerlab::testing::ShrunkExample("multiplicative_2layer.json", 8, 6, 3));
  const GhostedDisplay same = WithGhosts(plain);
  EXPECT_EQ(same.system.layers.size(), plain.layers.size());
  for (size_t k = 0; k < same.pattern_of.size(); ++k) EXPECT_EQ(same.pattern_of[k], static_cast<int>(k));
}

TEST(FoldedPath, RefusalsNameTheReason) {
  // A connection back onto the path: the message teaches the fold back.
  nlohmann::json cyclic = Birdbath();
  cyclic["elements"][2]["transmitted"] = "splitter";
  EXPECT_NE(CompileError(cyclic).find("cyclic connection"), std::string::npos);
  EXPECT_NE(CompileError(cyclic).find("\"fold\": \"back\""), std::string::npos);
  // Light reflected back needs each element's place on its way: a curved half mirror placed by the eye's
  // eye_relief, behind a plate without a place, does not say how far back the plate is.
  nlohmann::json unplaced = Pancake(0.01);
  unplaced["elements"] = {
      Eye("qa"),
      {{"type", "qwp"}, {"name", "qa"}, {"next", "hm"}},
      {{"type", "half_mirror"}, {"name", "hm"}, {"fold", "back"}, {"focal_length", "20 mm"}, {"transmitted", "front"}},
      Panel("front", "1 D", "backlight"),
      {{"type", "backlight"}, {"name", "backlight"}, {"luminance", "100 cd/m2"}}};
  const std::string why = CompileError(unplaced);
  EXPECT_NE(why.find("goes from \"hm\" back to \"qa\""), std::string::npos) << why;
  // A side that names no element: null is the way to say so.
  nlohmann::json empty = Birdbath();
  empty["elements"][1]["reflected"] = "";
  EXPECT_NE(CompileError(empty).find("null says that nothing is there"), std::string::npos);
  // A fold back is a splitter's: a full mirror there would return every ray.
  nlohmann::json mirror = Birdbath();
  mirror["elements"][2] = {{"type", "mirror"}, {"name", "bath"}, {"fold", "back"}, {"next", "outside"}};
  EXPECT_NE(CompileError(mirror).find("/elements/2/fold"), std::string::npos);
}

TEST(FoldedPath, ALosslessCavityIsCutAndSaidSo) {
  // Two mirrors of 90 % facing each other: the light between them fades too slowly to follow to its end.
  // The first is concave toward the eye (f = 100 mm): the light it reflects from behind meets its convex face.
  nlohmann::json e = nlohmann::json::array();
  e.push_back(Eye("m1"));
  e.push_back({{"type", "half_mirror"},
               {"name", "m1"},
               {"fold", "back"},
               {"reflectance", 0.9},
               {"transmittance", 0.1},
               {"gap", "20 mm"},
               {"transmitted", "m2"}});
  e.push_back({{"type", "half_mirror"},
               {"name", "m2"},
               {"fold", "back"},
               {"reflectance", 0.9},
               {"transmittance", 0.1},
               {"gap", "5 mm"},
               {"transmitted", "front"}});
  e[1]["focal_length"] = "100 mm";
  e.push_back(Panel("front", "0.5 D", "backlight"));
  e.back().erase("virtual_depth");
  e.back()["gap"] = "500 mm";
  e.push_back({{"type", "backlight"}, {"name", "backlight"}, {"luminance", "100 cd/m2"}});
  const DisplaySystem s = CompileJson({{"format", "layerlab-scene/1"}, {"elements", e}});
  std::string warnings;
  for (const std::string& w : s.warnings) warnings += w + "\n";
  EXPECT_NE(warnings.find("were cut after meeting one element 8 times"), std::string::npos) << warnings;
  EXPECT_NEAR(s.branches[0].optics_efficiency[1], 0.01, 1e-15);  // straight through both
  const Ghost* once = GhostBy(s, "m1.transmitted/m2.reflected/m1.reflected/m2.transmitted");
  ASSERT_NE(once, nullptr);
  EXPECT_NEAR(once->optics_efficiency[1], 0.01 * 0.81, 1e-15);  // once around the cavity
  EXPECT_NEAR(once->layers[0].position_m, s.layers[0].position_m + 10e-3, 1e-15);
  EXPECT_NEAR(s.layers[0].diopters, 1 / 525e-3, 1e-12);  // the mirrors' transmission has no power
  // Once around: reflected by the flat m2 at 25 mm, by m1's convex back (-10 D) at 30 mm, 505 mm to the panel.
  EXPECT_NEAR(once->layers[0].diopters, Diopters({{30e-3, -10}, {505e-3, 0}}), 1e-9);
}

// The most light a route can pass, over polarizations and channels: its Jones matrix's largest singular value
// squared, here of routes whose answer is plain.
TEST(FoldedPath, TheBrightestThroughARouteIsItsLargestSingularValueSquared) {
  const ElementRegistry registry = ElementRegistry::WithBuiltins();
  auto make = [&](const nlohmann::json& j) {
    Params p(j, Location{"scene.json", "/e"});
    return registry.create(p);
  };
  const auto vertical = make({{"type", "linear_polarizer"}, {"name", "p"}, {"axis", "90 deg"}, {"next", "x"}});
  const auto diagonal = make({{"type", "linear_polarizer"}, {"name", "q"}, {"axis", "45 deg"}, {"next", "x"}});
  const auto half = make({{"type", "half_mirror"},
                          {"name", "h"},
                          {"reflectance", 0.3},
                          {"transmittance", 0.6},
                          {"transmitted", "a"},
                          {"reflected", "b"}});
  const auto plate = make({{"type", "qwp"}, {"name", "w"}, {"fast_axis", "0 deg"}, {"next", "x"}});
  EXPECT_NEAR(BrightestThrough({{vertical.get(), 0}}, kWavelengths), 1, 1e-15);  // y passes whole
  EXPECT_NEAR(BrightestThrough({{half.get(), kReflectedPort}}, kWavelengths), 0.3, 1e-15);
  EXPECT_NEAR(BrightestThrough({{half.get(), kTransmittedPort}, {vertical.get(), 0}}, kWavelengths), 0.6, 1e-15);
  // Crossed polarizers pass nothing, with a polarizer at 45 deg between them a quarter (Malus twice).
  const auto horizontal = make({{"type", "linear_polarizer"}, {"name", "r"}, {"axis", "0 deg"}, {"next", "x"}});
  EXPECT_NEAR(BrightestThrough({{vertical.get(), 0}, {horizontal.get(), 0}}, kWavelengths), 0, 1e-15);
  EXPECT_NEAR(BrightestThrough({{vertical.get(), 0}, {diagonal.get(), 0}, {horizontal.get(), 0}}, kWavelengths), 0.25,
              1e-12);
  // A quarter-wave plate along x between the crossed pair: x stays x, nothing passes at its design wavelength.
  EXPECT_NEAR(BrightestThrough({{vertical.get(), 0}, {plate.get(), 0}, {horizontal.get(), 0}}, kWavelengths), 0, 1e-15);
}

}  // namespace
}  // namespace layerlab
