// A real lens in a scene: the compile's thick-lens transfer, the layer's
// exact ray map against an independent trace and the paraxial limit, the
// sampled map's bound, and the projections that read it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numbers>

#include "layerlab/elements/registry.h"
#include "layerlab/framework/json_file.h"
#include "layerlab/framework/random.h"
#include "layerlab/lenses/glass_absorption.h"
#include "layerlab/lenses/glass_catalog.h"
#include "layerlab/systems/compile.h"
#include "layerlab/systems/display_model.h"
#include "layerlab/systems/layer_ray_map.h"
#include "layerlab/systems/scene.h"
#include "lens_brute_force.h"

namespace layerlab {
namespace {

using lens_testing::BruteSurface;
using lens_testing::BruteTrace;

const std::string kExample = std::string(LAYERLAB_SOURCE_DIR) + "/examples/paper_prototype_la1608.json";
constexpr double kRadius = 38.6e-3, kThickness = 4.1e-3, kEyeRelief = 10e-3;

const DisplaySystem& Singlet() {
  static const DisplaySystem system = Compile(LoadScene(kExample));
  return system;
}

// A six-surface eyepiece read from the shipped .zmx, whose apertures cut part of the field.
const DisplaySystem& Plossl() {
  static const DisplaySystem system =
      Compile(LoadScene(std::string(LAYERLAB_SOURCE_DIR) + "/examples/paper_prototype_plossl.json"));
  return system;
}

// The thick lens's vertex matrix written from its two refractions and the
// glass between them: (1 0; -(n-1)/R 1), then (1 t/n; 0 1), then the flat back.
RayTransfer<double> HandThickLens(double n) {
  const double p1 = (n - 1) / kRadius;
  return {1 - kThickness * p1 / n, kThickness / n, -p1, 1};
}

TEST(RealLensCompile, LayersSitWhereTheThickLensMatrixImagesThem) {
  const DisplaySystem& s = Singlet();
  const double n = lenses::FindMaterial("N-BK7").Index(s.eye.channel_wavelengths_m[1]);
  const RayTransfer<double> lens = HandThickLens(n);
  ASSERT_EQ(s.layers.size(), 4u);
  for (const VirtualLayer& l : s.layers) {
    // pupil -> first vertex -> last vertex -> the panel, at its position on the path.
    const double behind = l.position_m - kEyeRelief - kThickness;
    const RayTransfer<double> m = RayTransfer<double>{}.then_gap(kEyeRelief).then(lens).then_gap(behind);
    EXPECT_NEAR(m.a / m.b, l.diopters, 1e-9) << l.name;
    EXPECT_NEAR(l.transfer.b, m.b, 1e-9 * std::abs(m.b)) << l.name;
    EXPECT_NEAR(l.transfer.c, m.c, 1e-9 * std::abs(m.c)) << l.name;
    EXPECT_NEAR(l.transfer.d, m.d, 1e-9) << l.name;
    EXPECT_NEAR(l.panel_distance_m, behind, 1e-12) << l.name << ": measured from the last vertex";
    ASSERT_TRUE(l.ray_map) << l.name;
  }
  EXPECT_NEAR(s.layers[0].diopters, 0.4, 1e-12);  // virtual_depth places them exactly
}

// Each branch loses, per channel, the lens's two uncoated surfaces (Fresnel at
// normal incidence, ((n - 1) / (n + 1))^2 each) and 4.1 mm of N-BK7's absorption.
TEST(RealLensCompile, BranchesLoseTheLensesSurfaceReflectionsAndAbsorption) {
  const DisplaySystem& s = Singlet();
  const lenses::Material& glass = lenses::FindMaterial("N-BK7");
  for (const Branch& b : s.branches)
    for (int c = 0; c < 3; ++c) {
      const double n = glass.Index(s.eye.channel_wavelengths_m[c]);
      const double surface = 1 - std::pow((n - 1) / (n + 1), 2);
      const double bulk = lenses::InternalTransmittance(glass, s.eye.channel_wavelengths_m[c], kThickness);
      EXPECT_GT(bulk, 0.99);
      EXPECT_NEAR(b.optics_efficiency[c], 0.5 * surface * surface * bulk, 1e-12) << b.name << " channel " << c;
    }
}

// The paraxial limit of the exact map is the compile's affine map U = D p + u.
TEST(RealLensCompile, TheExactMapsParaxialLimitIsTheRayTransfer) {
  for (const VirtualLayer& l : Singlet().layers) {
    const LayerRayMap& exact = l.ray_map->exact();
    for (const auto& [p, u] : std::vector<std::pair<double, double>>{{1e-7, 0}, {0, 1e-7}, {-2e-7, 1e-7}}) {
      const auto U = exact.Trace(1, p, -p, u, 2 * u);
      ASSERT_TRUE(U);
      const double scale = std::abs(l.diopters * p) + std::abs(u);
      EXPECT_NEAR((*U)[0], l.diopters * p + u, 1e-9 * scale) << l.name;
      EXPECT_NEAR((*U)[1], -l.diopters * p + 2 * u, 1e-9 * 2 * scale) << l.name;
    }
  }
}

// Through ideal optics the exact map is the affine one for any ray.
TEST(RealLensCompile, ThroughIdealOpticsTheMapIsAffine) {
  const DisplaySystem ideal = Compile(LoadScene(std::string(LAYERLAB_SOURCE_DIR) + "/examples/paper_prototype.json"));
  for (const VirtualLayer& l : ideal.layers) {
    EXPECT_FALSE(l.ray_map) << "ideal optics keep the affine fast path";
    const LayerRayMap exact(l, ideal.eye.channel_wavelengths_m);
    for (double p : {-3e-3, 0.0, 2.5e-3})
      for (double u : {-0.3, 0.05, 0.31}) {
        const auto U = exact.Trace(0, p, p, u, -u);
        ASSERT_TRUE(U);
        EXPECT_NEAR((*U)[0], l.diopters * p + u, 1e-12) << l.name;
        EXPECT_NEAR((*U)[1], l.diopters * p - u, 1e-12) << l.name;
      }
  }
}

// Each channel's ray against a trace written apart from lenses/ (lens_brute_force.h),
// carried to the panel by hand: to 1e-9 m on the panel.
TEST(RealLensCompile, EachChannelsPanelPointAgreesWithAnIndependentTrace) {
  const DisplaySystem& s = Singlet();
  for (const VirtualLayer& l : s.layers) {
    for (int c = 0; c < 3; ++c) {
      const double n = lenses::FindMaterial("N-BK7").Index(s.eye.channel_wavelengths_m[c]);
      std::vector<BruteSurface> lens(2);
      lens[0].vertex_z = kEyeRelief, lens[0].c = 1 / kRadius, lens[0].n_after = n;
      lens[1].vertex_z = kEyeRelief + kThickness, lens[1].n_after = 1;
      for (const auto& [p, u] : std::vector<std::pair<double, double>>{{0, 0.32}, {2e-3, -0.2}, {-3e-3, 0.1}}) {
        const auto r =
            BruteTrace(lens, 1.0, Eigen::Vector3d(p, 0.5 * p, 0), Eigen::Vector3d(u, 0.3 * u, 1).normalized());
        ASSERT_TRUE(r.ok);
        const Eigen::Vector3d at_panel = r.point + r.direction * ((l.position_m - r.point.z()) / r.direction.z());
        const auto U = l.ray_map->exact().Trace(c, p, 0.5 * p, u, 0.3 * u);
        ASSERT_TRUE(U);
        EXPECT_NEAR((*U)[0] * l.transfer.b, at_panel.x(), 1e-9) << l.name << " channel " << c;
        EXPECT_NEAR((*U)[1] * l.transfer.b, at_panel.y(), 1e-9) << l.name << " channel " << c;
      }
    }
  }
}

void ExpectWithinAHundredth(const VirtualLayer& l);

// A lens tilted and decentred in its mount: the same rays traced by the
// independent tracer in the lens's own frame (R = Ry(tilt_y) Rx(tilt_x) about
// the first vertex, then shifted), written here from the rotations' matrices.
TEST(RealLensCompile, ATiltedDecentredLensIsTracedAsMounted) {
  nlohmann::json scene = ReadJsonFile(kExample);
  for (nlohmann::json& e : scene["elements"])
    if (e["name"] == "lens") e["tilt"] = {"2 deg", "-1.5 deg"}, e["decentre"] = {"0.8 mm", "-0.5 mm"};
  const DisplaySystem s = Compile(ParseScene(scene, kExample, ElementRegistry::WithBuiltins()));
  EXPECT_NE(std::find_if(s.warnings.begin(), s.warnings.end(),
                         [](const std::string& w) { return w.find("tilted or decentred") != std::string::npos; }),
            s.warnings.end());
  const double tx = 2 * std::numbers::pi / 180, ty = -1.5 * std::numbers::pi / 180;
  Eigen::Matrix3d rx, ry;
  rx << 1, 0, 0, 0, std::cos(tx), -std::sin(tx), 0, std::sin(tx), std::cos(tx);
  ry << std::cos(ty), 0, std::sin(ty), 0, 1, 0, -std::sin(ty), 0, std::cos(ty);
  const Eigen::Matrix3d R = ry * rx;
  const Eigen::Vector3d vertex(0.8e-3, -0.5e-3, kEyeRelief), on_axis(0, 0, kEyeRelief);
  for (const VirtualLayer& l : s.layers) {
    EXPECT_NEAR(l.diopters, Singlet().layers[&l - &s.layers[0]].diopters, 1e-12) << "first order: the centred lens";
    for (int c = 0; c < 3; ++c) {
      const double n = lenses::FindMaterial("N-BK7").Index(s.eye.channel_wavelengths_m[c]);
      std::vector<BruteSurface> lens(2);
      lens[0].vertex_z = kEyeRelief, lens[0].c = 1 / kRadius, lens[0].n_after = n;
      lens[1].vertex_z = kEyeRelief + kThickness, lens[1].n_after = 1;
      for (const auto& [p, u] : std::vector<std::pair<double, double>>{{0, 0.3}, {2e-3, -0.2}, {-3e-3, 0.1}}) {
        const Eigen::Vector3d o(p, 0.5 * p, 0), d = Eigen::Vector3d(u, 0.3 * u, 1).normalized();
        const Eigen::Vector3d o_local = R.transpose() * (o - vertex) + on_axis, d_local = R.transpose() * d;
        const auto r = BruteTrace(lens, 1.0, o_local, d_local);
        ASSERT_TRUE(r.ok);
        const Eigen::Vector3d exit = R * (r.point - on_axis) + vertex, direction = R * r.direction;
        const Eigen::Vector3d at_panel = exit + direction * ((l.position_m - exit.z()) / direction.z());
        const auto U = l.ray_map->exact().Trace(c, p, 0.5 * p, u, 0.3 * u);
        ASSERT_TRUE(U);
        EXPECT_NEAR((*U)[0] * l.transfer.b, at_panel.x(), 1e-9) << l.name << " channel " << c;
        EXPECT_NEAR((*U)[1] * l.transfer.b, at_panel.y(), 1e-9) << l.name << " channel " << c;
      }
    }
  }
}

TEST(RealLensCompile, AThinLensRefusesTiltWithTheReason) {
  nlohmann::json scene = ReadJsonFile(std::string(LAYERLAB_SOURCE_DIR) + "/examples/paper_prototype.json");
  for (nlohmann::json& e : scene["elements"])
    if (e["name"] == "lens") e["tilt"] = {"1 deg", "0 deg"};
  try {
    Compile(ParseScene(scene, "scene.json", ElementRegistry::WithBuiltins()));
    FAIL() << "a tilted thin lens compiled";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("/elements/1/tilt: an ideal thin lens is first-order optics"),
              std::string::npos)
        << e.what();
  }
}

// The sampled map within 0.01 px of the exact trace at rays it was not refined on.
TEST(RealLensCompile, TheSampledMapStaysWithinAHundredthOfAPixel) {
  for (const VirtualLayer& l : Singlet().layers) ExpectWithinAHundredth(l);
  for (const VirtualLayer& l : Plossl().layers) ExpectWithinAHundredth(l);
}

void ExpectWithinAHundredth(const VirtualLayer& l) {
  {
    const SampledRayMap& map = *l.ray_map;
    const RayMapDomain& d = map.domain();
    SplitMix64 random(20261205);
    double worst = 0;
    int compared = 0;
    for (int k = 0; k < 20000; ++k) {
      auto in = [&](double lo, double hi) { return lo + random.uniform() * (hi - lo); };
      const double px = in(d.pupil_min_m[0], d.pupil_max_m[0]), py = in(d.pupil_min_m[1], d.pupil_max_m[1]);
      const double ux = in(d.tan_min[0], d.tan_max[0]), uy = in(d.tan_min[1], d.tan_max[1]);
      const int c = k % 3;
      const auto exact = map.exact().Trace(c, px, py, ux, uy), grid = map.Lookup(c, px, py, ux, uy);
      ASSERT_EQ(exact.has_value(), grid.has_value());
      if (!exact) continue;
      ++compared;
      worst = std::max({worst, std::abs((*exact)[0] - (*grid)[0]) / l.tan_pitch_x,
                        std::abs((*exact)[1] - (*grid)[1]) / l.tan_pitch_y});
    }
    EXPECT_GT(compared, 10000) << l.name;
    EXPECT_LT(worst, 0.01) << l.name;
    EXPECT_LE(map.bound_pixels(), kMapTolerancePixels) << l.name;
  }
}

// A mapped projection reads, per channel, the pixel the exact trace names.
void ExpectGathersWhereRaysLand(const DisplaySystem& s);

TEST(RealLensCompile, TheProjectionGathersWhereEachChannelsRayLands) {
  ExpectGathersWhereRaysLand(Singlet());
  ExpectGathersWhereRaysLand(Plossl());
}

void ExpectGathersWhereRaysLand(const DisplaySystem& s) {
  LightFieldGeometry g = DisplayLightFieldGeometry(s);
  g.cols = 40, g.rows = 20, g.views_x = 3, g.views_y = 3;
  const DisplayModel model(s, g);
  for (size_t k = 0; k < model.layer_count(); ++k) {
    const LayerProjection& P = model.projection(k);
    ASSERT_TRUE(P.mapped());
    EXPECT_FALSE(P.one_tap());
    LayerPattern t(P.cols(), P.rows(), 0);
    for (size_t i = 0; i < t.rgb.size(); ++i) t.rgb[i] = float(i % 9973) / 9973.0f;
    std::vector<float> out(g.pixels_per_view() * 3);
    const size_t view = 4;
    P.Gather(view, t.rgb.data(), out.data());
    const double px = g.view_x(1), py = g.view_y(1);
    const LayerSampler& sampler = P.sampler();
    int differ = 0;
    for (int i = 0; i < g.rows; ++i)
      for (int j = 0; j < g.cols; ++j)
        for (int c = 0; c < 3; ++c) {
          const auto U = P.ray_map()->exact().Trace(c, px, py, (g.pixel_x(j) - px) / g.origin_z_m,
                                                    (g.pixel_y(i) - py) / g.origin_z_m);
          const RayTaps taps = U ? sampler.At((*U)[0], (*U)[1]) : RayTaps{};
          float expected = 0;
          for (int q = 0; q < taps.count; ++q) expected += taps.weight[q] * t.rgb[size_t(taps.index[q]) * 3 + c];
          differ += out[(size_t(i) * g.cols + j) * 3 + c] != expected;
        }
    // The grid may put a ray within 0.005 px of a pixel edge on the other side: allow a handful.
    EXPECT_LE(differ, 3) << "layer " << k;
  }
}

}  // namespace
}  // namespace layerlab
