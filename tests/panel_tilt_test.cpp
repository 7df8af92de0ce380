// A tilted panel (lc_panel "tilt"): its layer is mapped, and the map meets the
// tilted plane where an independent ray-plane intersection, written here from
// the rotations' matrices, puts the ray; zero tilt changes nothing; the key is
// read with its units and range.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include <Eigen/Core>

#include "layerlab/elements/registry.h"
#include "layerlab/framework/json_file.h"
#include "layerlab/systems/compile.h"
#include "layerlab/systems/layer_ray_map.h"
#include "layerlab/systems/projection.h"
#include "layerlab/systems/scene.h"

namespace layerlab {
namespace {

const std::string kIdeal = std::string(LAYERLAB_SOURCE_DIR) + "/examples/paper_prototype.json";
const std::string kSinglet = std::string(LAYERLAB_SOURCE_DIR) + "/examples/paper_prototype_la1608.json";
constexpr double kDeg = std::numbers::pi / 180;

DisplaySystem CompileEdited(const std::string& file, const std::string& panel, const nlohmann::json& tilt,
                            const nlohmann::json& offset = nullptr) {
  nlohmann::json scene = ReadJsonFile(file);
  for (nlohmann::json& e : scene["elements"])
    if (e["name"] == panel) {
      if (!tilt.is_null()) e["tilt"] = tilt;
      if (!offset.is_null()) e["offset"] = offset;
    }
  return Compile(ParseScene(scene, file, ElementRegistry::WithBuiltins()));
}

const VirtualLayer& Layer(const DisplaySystem& s, const std::string& name) {
  for (const VirtualLayer& l : s.layers)
    if (l.name == name) return l;
  throw Error("no layer " + name);
}

// The ray from pupil point p with tan-direction u through the ideal 75 mm
// magnifier at 10 mm (the half mirror folds but has no power), met by the
// plane through C with normal R z; its in-plane coordinates along R x and
// R y, added to C's, over b.
std::array<double, 2> HandTiltedHit(const VirtualLayer& l, double tx, double ty, double ox, double oy,
                                    Eigen::Vector2d p, Eigen::Vector2d u) {
  const double f = 75e-3, lens_z = 10e-3;
  const Eigen::Vector2d h = p + u * lens_z, slope = u - h / f;
  const Eigen::Vector3d o(h.x(), h.y(), lens_z), d(slope.x(), slope.y(), 1);
  Eigen::Matrix3d rx, ry;
  rx << 1, 0, 0, 0, std::cos(tx), -std::sin(tx), 0, std::sin(tx), std::cos(tx);
  ry << std::cos(ty), 0, std::sin(ty), 0, 1, 0, -std::sin(ty), 0, std::cos(ty);
  const Eigen::Matrix3d R = ry * rx;
  const double side = l.transfer.b < 0 ? -1 : 1;
  const Eigen::Vector3d C(side * ox, side * oy, l.position_m);
  const Eigen::Vector3d n = R.col(2);
  const double t = (C - o).dot(n) / d.dot(n);
  const Eigen::Vector3d hit = o + t * d - C;
  return {(C.x() + hit.dot(R.col(0))) / l.transfer.b, (C.y() + hit.dot(R.col(1))) / l.transfer.b};
}

TEST(PanelTilt, ATiltedPanelIsMetWhereTheRayCrossesItsTiltedPlane) {
  const double tx = 3 * kDeg, ty = -2 * kDeg, ox = 1e-3, oy = -0.5e-3;
  const DisplaySystem s = CompileEdited(kIdeal, "rear_a", {"3 deg", "-2 deg"}, {"1 mm", "-0.5 mm"});
  const VirtualLayer& l = Layer(s, "rear_a");
  ASSERT_NE(l.ray_map, nullptr) << "a tilted panel's layer is mapped";
  EXPECT_EQ(Layer(s, "front_a").ray_map, nullptr) << "the untilted panels keep the affine path";
  EXPECT_TRUE(LayerProjection(l, LightFieldGeometry{}, Sampling::kNearest).mapped());
  bool warned = false;
  for (const std::string& w : s.warnings) warned |= w.find("panel \"rear_a\" is tilted") != std::string::npos;
  EXPECT_TRUE(warned);
  for (const auto& [p, u] : std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>>{
           {{0, 0}, {0, 0}}, {{2e-3, -1e-3}, {0.2, 0.1}}, {{-3e-3, 2.5e-3}, {-0.25, 0.12}}}) {
    const std::array<double, 2> want = HandTiltedHit(l, tx, ty, ox, oy, p, u);
    for (int c = 0; c < 3; ++c) {
      const auto U = l.ray_map->exact().Trace(c, p.x(), p.y(), u.x(), u.y());
      ASSERT_TRUE(U);
      EXPECT_NEAR((*U)[0], want[0], 1e-12) << c;
      EXPECT_NEAR((*U)[1], want[1], 1e-12) << c;
      const auto sampled = l.ray_map->Lookup(c, p.x(), p.y(), u.x(), u.y());
      ASSERT_TRUE(sampled);
      EXPECT_NEAR((*sampled)[0], want[0], 0.01 * l.tan_pitch_x) << "the sampled map within 0.01 px";
      EXPECT_NEAR((*sampled)[1], want[1], 0.01 * l.tan_pitch_y);
    }
  }
}

// A panel turned about y alone, centred: a ray the magnifier makes parallel
// to the axis at height h meets it at h / cos(ty) along its own x axis (the
// plane leans away by h tan ty there), and at h along y, which it keeps.
TEST(PanelTilt, AParallelRayIsForeshortenedByTheCosineOfTheTilt) {
  const double ty = 10 * kDeg, h = 2e-3, f = 75e-3, lens_z = 10e-3;
  const DisplaySystem s = CompileEdited(kIdeal, "front_b", {"0 deg", "10 deg"});
  const VirtualLayer& l = Layer(s, "front_b");
  ASSERT_NE(l.ray_map, nullptr);
  const double p = h * (1 - lens_z / f), u = h / f;  // height h at the lens, leaving it parallel
  const auto along_x = l.ray_map->exact().Trace(1, p, 0, u, 0), along_y = l.ray_map->exact().Trace(1, 0, p, 0, u);
  ASSERT_TRUE(along_x && along_y);
  EXPECT_NEAR((*along_x)[0] * l.transfer.b, h / std::cos(ty), 1e-15);
  EXPECT_NEAR((*along_x)[1], 0.0, 1e-15);
  EXPECT_NEAR((*along_y)[1] * l.transfer.b, h, 1e-15);
  EXPECT_NEAR((*along_y)[0], 0.0, 1e-15);
}

TEST(PanelTilt, ZeroTiltChangesNothing) {
  const DisplaySystem plain = Compile(LoadScene(kSinglet));
  const DisplaySystem zero = CompileEdited(kSinglet, "rear_a", {"0 deg", "0 deg"});
  const VirtualLayer &a = Layer(plain, "rear_a"), &b = Layer(zero, "rear_a");
  ASSERT_NE(a.ray_map, nullptr);
  ASSERT_NE(b.ray_map, nullptr);
  for (const auto& [p, u] : std::vector<std::pair<double, double>>{{0, 0.1}, {2e-3, -0.2}, {-3e-3, 0.25}}) {
    for (int c = 0; c < 3; ++c) {
      const auto A = a.ray_map->exact().Trace(c, p, 0.5 * p, u, 0.3 * u),
                 B = b.ray_map->exact().Trace(c, p, 0.5 * p, u, 0.3 * u);
      ASSERT_TRUE(A && B);
      EXPECT_EQ(*A, *B);
      EXPECT_EQ(*a.ray_map->Lookup(c, p, 0.5 * p, u, 0.3 * u), *b.ray_map->Lookup(c, p, 0.5 * p, u, 0.3 * u));
    }
  }
  const DisplaySystem ideal = CompileEdited(kIdeal, "rear_a", {"0 deg", "0 deg"});
  for (const VirtualLayer& l : ideal.layers) EXPECT_EQ(l.ray_map, nullptr) << "zero tilt stays on the affine path";
  EXPECT_TRUE(ideal.warnings.empty() || ideal.warnings.front().find("tilted") == std::string::npos);
}

void ExpectRefused(const nlohmann::json& tilt, const std::string& message) {
  try {
    CompileEdited(kIdeal, "front_a", tilt);
    FAIL() << "accepted tilt " << tilt.dump();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
  }
}

TEST(PanelTilt, BadTiltsAreRefusedNamingTheKey) {
  ExpectRefused({"40 deg", "0 deg"}, "/elements/3/tilt: at most 0.5 rad (28.6 deg) either way");
  ExpectRefused({"0 deg", "-0.6 rad"}, "/elements/3/tilt: at most 0.5 rad");
  ExpectRefused({"1 mm", "0 deg"}, "/elements/3/tilt/0");
  ExpectRefused({"1 deg", "2 deg", "3 deg"}, "/elements/3/tilt: expected two values [x, y], got 3");
  ExpectRefused("nan deg", "/elements/3/tilt");
}

}  // namespace
}  // namespace layerlab
