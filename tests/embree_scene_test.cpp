// The Embree wrapper: closest hits with their barycentrics and normals, and
// the refusals that keep Embree from aborting or silently missing.
#include <cmath>
#include <limits>
#include <vector>

#include "layerlab/framework/error.h"
#include "layerlab/targets/embree_scene.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

using V = std::array<double, 3>;
using T = std::array<uint32_t, 3>;

std::string AddError(const std::vector<V>& vertices, const std::vector<T>& triangles) {
  EmbreeScene scene;
  try {
    scene.AddTriangles("bad.obj", vertices, triangles);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(EmbreeSceneTest, ClosestHitReportsDistanceBarycentricsAndNormal) {
  EmbreeScene scene;
  std::vector<V> far_triangle{{0, 0, 2}, {1, 0, 2}, {0, 1, 2}};
  std::vector<V> near_triangle{{0, 0, 1}, {1, 0, 1}, {0, 1, 1}};
  std::vector<T> one{{0, 1, 2}};
  unsigned far_id = scene.AddTriangles("far", far_triangle, one);
  unsigned near_id = scene.AddTriangles("near", near_triangle, one);
  scene.Commit();

  RayHit hit = scene.Intersect({0.25f, 0.125f, 0.0f}, {0.0f, 0.0f, 1.0f});
  ASSERT_TRUE(hit.hit());
  EXPECT_EQ(hit.geom_id, near_id);
  EXPECT_EQ(hit.prim_id, 0u);
  EXPECT_FLOAT_EQ(hit.t, 1.0f);
  // p = (1 - u - v) p0 + u p1 + v p2 = (u, v, 1).
  EXPECT_NEAR(hit.u, 0.25f, 1e-6);
  EXPECT_NEAR(hit.v, 0.125f, 1e-6);
  // (p1 - p0) x (p2 - p0) = x cross y = +z.
  EXPECT_FLOAT_EQ(hit.normal[0], 0.0f);
  EXPECT_FLOAT_EQ(hit.normal[1], 0.0f);
  EXPECT_GT(hit.normal[2], 0.0f);

  // Starting beyond the near triangle finds the far one; an unnormalized direction scales t.
  RayHit beyond = scene.Intersect({0.25f, 0.125f, 0.0f}, {0.0f, 0.0f, 2.0f}, 0.75f);
  EXPECT_EQ(beyond.geom_id, far_id);
  EXPECT_FLOAT_EQ(beyond.t, 1.0f);

  RayHit miss = scene.Intersect({2.0f, 2.0f, 0.0f}, {0.0f, 0.0f, 1.0f});
  EXPECT_FALSE(miss.hit());
  EXPECT_EQ(miss.geom_id, kNoGeometry);
  EXPECT_FALSE(scene.Intersect({0.25f, 0.125f, 0.0f}, {0.0f, 0.0f, -1.0f}).hit());
  EXPECT_FALSE(scene.Intersect({0.25f, 0.125f, 0.0f}, {0.0f, 0.0f, 1.0f}, 0.0f, 0.5f).hit());
}

TEST(EmbreeSceneTest, RefusesNonFiniteVerticesNamingMeshAndVertex) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(AddError({{0, 0, 1}, {nan, 0, 1}, {0, 1, 1}}, {{0, 1, 2}}),
            "bad.obj: vertex 1 is (nan, 0, 1) after placement; every coordinate must be finite (in single precision)");
  // Finite as a double, infinite as the float Embree stores.
  EXPECT_EQ(AddError({{0, 0, 1}, {1, 0, 1}, {0, 1e300, 1}}, {{0, 1, 2}}),
            "bad.obj: vertex 2 is (0, 1e+300, 1) after placement; every coordinate must be finite (in single "
            "precision)");
  EXPECT_EQ(AddError({{0, 0, 1}, {1, 0, 1}, {0, 1, 1}}, {{0, 1, 3}}),
            "bad.obj: triangle 0 uses vertex 3, beyond the 3 vertices");
  EXPECT_EQ(AddError({}, {}), "bad.obj: the mesh has no triangles");
}

TEST(EmbreeSceneTest, RefusesToTraceNonFiniteRays) {
  EmbreeScene scene;
  std::vector<V> triangle{{0, 0, 1}, {1, 0, 1}, {0, 1, 1}};
  std::vector<T> one{{0, 1, 2}};
  scene.AddTriangles("tri", triangle, one);
  scene.Commit();
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  auto message = [&](std::array<float, 3> o, std::array<float, 3> d, float t_near) {
    try {
      scene.Intersect(o, d, t_near);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(message({nan, 0, 0}, {0, 0, 1}, 0),
            "Embree: internal error: refusing to trace the ray from (nan, 0, 0) along (0, 0, 1) for t in [0, inf]");
  EXPECT_EQ(message({0, 0, 0}, {0, inf, 1}, 0),
            "Embree: internal error: refusing to trace the ray from (0, 0, 0) along (0, inf, 1) for t in [0, inf]");
  EXPECT_EQ(message({0, 0, 0}, {0, 0, 0}, 0),
            "Embree: internal error: refusing to trace the ray from (0, 0, 0) along (0, 0, 0) for t in [0, inf]");
  EXPECT_EQ(message({0, 0, 0}, {0, 0, 1}, -1),
            "Embree: internal error: refusing to trace the ray from (0, 0, 0) along (0, 0, 1) for t in [-1, inf]");
}

TEST(EmbreeSceneTest, RefusesGeometryAfterCommitAndTracingBefore) {
  EmbreeScene scene;
  std::vector<V> triangle{{0, 0, 1}, {1, 0, 1}, {0, 1, 1}};
  std::vector<T> one{{0, 1, 2}};
  EXPECT_THROW(scene.Intersect({0, 0, 0}, {0, 0, 1}), Error);
  scene.AddTriangles("tri", triangle, one);
  scene.Commit();
  EXPECT_THROW(scene.AddTriangles("late", triangle, one), Error);
}

}  // namespace
}  // namespace layerlab
