// Pupil swim against independent computations: none through ideal optics,
// and behind the LA1608 singlet the direction found by a fixed-point search
// with the brute-force tracer of lens_brute_force.h.
#include <gtest/gtest.h>

#include <cmath>

#include "layerlab/framework/units.h"
#include "layerlab/lenses/glass_catalog.h"
#include "layerlab/systems/compile.h"
#include "layerlab/systems/pupil_swim.h"
#include "layerlab/systems/scene.h"
#include "lens_brute_force.h"

namespace layerlab {
namespace {

using lens_testing::BruteSurface;
using lens_testing::BruteTrace;

const std::string kSource = LAYERLAB_SOURCE_DIR;

// Through ideal optics the exact map is U = D p + u: a point is seen along
// U - D p from every pupil point, the parallax of a point at its depth, and
// MeasurePupilSwim reports 0 without tracing.
TEST(PupilSwim, IdealOpticsDoNotSwim) {
  const DisplaySystem ideal = Compile(LoadScene(kSource + "/examples/paper_prototype.json"));
  for (const VirtualLayer& l : ideal.layers) {
    const LayerRayMap exact(l, ideal.eye.channel_wavelengths_m);
    const std::array<double, 2> U = {0.27, -0.11};
    const auto u0 = ApparentDirection(exact, 1, {0, 0}, U);
    ASSERT_TRUE(u0);
    for (const std::array<double, 2> p : {std::array<double, 2>{2e-3, 0}, {-1.5e-3, 2.5e-3}}) {
      const auto u = ApparentDirection(exact, 1, p, U);
      ASSERT_TRUE(u);
      for (int a = 0; a < 2; ++a) EXPECT_NEAR((*u)[a], (*u0)[a] - l.diopters * p[a], 1e-13) << l.name;
    }
  }
  for (const LayerSwim& s : MeasurePupilSwim(ideal, 2e-3, 2)) {
    EXPECT_FALSE(s.real_optics);
    EXPECT_EQ(s.max_arcmin, 0.0) << s.layer;
    EXPECT_EQ(s.samples.size(), 9u * 8u);  // 9 field points, 2 x 2 pupil points each side on each axis
  }
}

// Behind the singlet (R 38.6 mm, 4.1 mm of N-BK7, 10 mm from the pupil) the
// direction toward a layer point from a pupil point: the brute-force tracer
// carried to the panel, and u moved by the miss until it lands (the map is
// near the identity in u, so the iteration contracts).
TEST(PupilSwim, TheSingletsDirectionIsWhereAnIndependentTraceLands) {
  const DisplaySystem s = Compile(LoadScene(kSource + "/examples/paper_prototype_la1608.json"));
  const double n = lenses::FindMaterial("N-BK7").Index(s.eye.channel_wavelengths_m[1]);
  std::vector<BruteSurface> lens(2);
  lens[0].vertex_z = 10e-3, lens[0].c = 1 / 38.6e-3, lens[0].n_after = n;
  lens[1].vertex_z = 14.1e-3, lens[1].n_after = 1;
  const VirtualLayer& l = s.layers.front();
  ASSERT_TRUE(l.ray_map);
  auto brute = [&](const std::array<double, 2>& p, const std::array<double, 2>& u) {
    const auto r = BruteTrace(lens, 1.0, Eigen::Vector3d(p[0], p[1], 0), Eigen::Vector3d(u[0], u[1], 1).normalized());
    EXPECT_TRUE(r.ok);
    const Eigen::Vector3d at = r.point + r.direction * ((l.position_m - r.point.z()) / r.direction.z());
    return std::array<double, 2>{at.x() / l.transfer.b, at.y() / l.transfer.b};
  };
  // A field point of MeasurePupilSwim's: 0.9 of the half field right of the layer's centre.
  const std::array<double, 2> U = {l.eye_from_layer_tan_x + 0.9 * 0.5 * l.cols * l.tan_pitch_x, l.eye_from_layer_tan_y};
  const std::vector<LayerSwim> swim = MeasurePupilSwim(s, 2e-3, 2);
  ASSERT_EQ(swim.size(), s.layers.size());
  std::array<double, 2> u0{};
  for (const std::array<double, 2> p : {std::array<double, 2>{0, 0}, {2e-3, 0}, {0, -1e-3}}) {
    std::array<double, 2> u = {U[0] - l.diopters * p[0], U[1] - l.diopters * p[1]};
    for (int k = 0; k < 200; ++k) {
      const std::array<double, 2> at = brute(p, u);
      u = {u[0] - (at[0] - U[0]), u[1] - (at[1] - U[1])};
    }
    const auto found = ApparentDirection(l.ray_map->exact(), 1, p, U);
    ASSERT_TRUE(found);
    EXPECT_NEAR((*found)[0], u[0], 1e-9) << p[0] << ", " << p[1];  // the brute tracer's own precision
    EXPECT_NEAR((*found)[1], u[1], 1e-9) << p[0] << ", " << p[1];
    if (p[0] == 0 && p[1] == 0) {
      u0 = u;
      continue;
    }
    // The swim there, as angles: against the parallax of a point at the layer's depth.
    bool seen = false;
    for (const SwimSample& sample : swim.front().samples) {
      if (sample.field_tan != U || sample.pupil_m != p) continue;
      seen = true;
      for (int a = 0; a < 2; ++a)
        EXPECT_NEAR(sample.swim[a], std::atan(u[a]) - std::atan(u0[a] - l.diopters * p[a]), 1e-9);
    }
    EXPECT_TRUE(seen) << "MeasurePupilSwim has the point";
  }
  for (const LayerSwim& layer : swim) {
    EXPECT_TRUE(layer.real_optics);
    EXPECT_GT(layer.max_arcmin, 0.5) << layer.layer;  // the singlet swims
  }
}

}  // namespace
}  // namespace layerlab
