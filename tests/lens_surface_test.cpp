// Surface intersections and normals against independent computations: the
// sphere's analytic intersection (|p - center| = R), bisection on the sag for
// conics and aspheres, the finite-difference slope, the folded Fresnel sag.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "layerlab/lenses/surface.h"
#include "layerlab/tests/lens_brute_force.h"

namespace layerlab::lenses {
namespace {

using lens_testing::BruteCrossing;
using lens_testing::BruteNormal;
using lens_testing::BruteSurface;

constexpr double kMm = 1e-3;

std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> Rays() {
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> rays;
  for (double x : {-9.0, -2.0, 0.0, 3.5, 8.0}) {
    for (double y : {-6.0, 0.0, 1.0, 7.0}) {
      for (const Eigen::Vector3d& d :
           {Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(0.1, -0.05, 1), Eigen::Vector3d(-0.2, 0.15, 1)}) {
        rays.push_back({Eigen::Vector3d(x * kMm, y * kMm, -5 * kMm), d.normalized()});
      }
    }
  }
  return rays;
}

SurfaceShape Shape(double c, double k = 0, std::vector<double> a = {}, double pitch = 0) {
  SurfaceShape s;
  s.curvature_per_m = c;
  s.conic = k;
  s.even_asphere = std::move(a);
  s.fresnel_pitch_m = pitch;
  return s;
}

TEST(LensSurface, SphereIntersectionIsTheAnalyticOne) {
  for (double radius : {30 * kMm, -25 * kMm, 200 * kMm}) {
    const Surface surface(Shape(1 / radius));
    const Eigen::Vector3d center(0, 0, radius);
    for (const auto& [o, d] : Rays()) {
      // |o + t d - center|^2 = R^2; the vertex-side root has (z - R) of the sign opposite to R.
      const Eigen::Vector3d oc = o - center;
      const double b = oc.dot(d);
      const double disc = b * b - (oc.squaredNorm() - radius * radius);
      ASSERT_GT(disc, 0);
      double t = -b - std::sqrt(disc);
      if ((o + t * d - center).z() * radius > 0) t = -b + std::sqrt(disc);
      const SurfaceHit hit = surface.Intersect(o, d);
      ASSERT_EQ(hit.status, HitStatus::kHit);
      EXPECT_NEAR(hit.t, t, 1e-14) << "R " << radius;
      // The sphere's normal is along the radius.
      const Eigen::Vector3d radial = (center - hit.point).normalized() * (radius > 0 ? 1 : -1);
      EXPECT_LT((hit.normal - radial).norm(), 1e-13);
    }
  }
}

void ExpectBisectionAgrees(const SurfaceShape& shape) {
  const Surface surface(shape);
  const BruteSurface brute{0, shape.curvature_per_m, shape.conic, shape.even_asphere, shape.fresnel_pitch_m, 1};
  for (const auto& [o, d] : Rays()) {
    const SurfaceHit hit = surface.Intersect(o, d);
    ASSERT_EQ(hit.status, HitStatus::kHit) << o.transpose();
    EXPECT_NEAR(hit.t, BruteCrossing(brute, o, d), 1e-13) << o.transpose();
    EXPECT_LT((hit.normal - BruteNormal(brute, hit.point)).norm(), 1e-9);
  }
}

TEST(LensSurface, ConicsMatchBisectionOnTheSag) {
  ExpectBisectionAgrees(Shape(1 / (40 * kMm), -1));    // paraboloid
  ExpectBisectionAgrees(Shape(1 / (40 * kMm), -3.2));  // hyperboloid
  ExpectBisectionAgrees(Shape(-1 / (35 * kMm), 0.8));  // oblate ellipsoid, concave
  ExpectBisectionAgrees(Shape(1 / (40 * kMm), -0.5));  // prolate ellipsoid
}

TEST(LensSurface, EvenAspheresMatchBisectionOnTheSag) {
  ExpectBisectionAgrees(Shape(1 / (30 * kMm), -1, {2e3, -1e6}));
  ExpectBisectionAgrees(Shape(-1 / (50 * kMm), 0.5, {-4e3, 3e6, -1e9}));
  ExpectBisectionAgrees(Shape(0, 0, {1e4}));  // a pure r^4 plate
}

TEST(LensSurface, AsphereHitsAreOnTheSurfaceOrReportedLost) {
  // A strong asphere and rays that graze it: every hit returned lies on the sag
  // (never a wrong point), every other ray is reported.
  const SurfaceShape shape = Shape(1 / (20 * kMm), -1, {-3e5, 5e8});
  const Surface surface(shape);
  const BruteSurface brute{0, shape.curvature_per_m, shape.conic, shape.even_asphere, 0, 1};
  int hits = 0;
  for (double angle = 0; angle < 1.5; angle += 0.05) {
    for (double x : {-12.0, -5.0, 0.0, 4.0, 10.0}) {
      const Eigen::Vector3d o(x * kMm, 0, -2 * kMm);
      const Eigen::Vector3d d(std::sin(angle), 0, std::cos(angle));
      const SurfaceHit hit = surface.Intersect(o, d);
      if (hit.status != HitStatus::kHit) continue;
      ++hits;
      const double r = std::hypot(hit.point.x(), hit.point.y());
      EXPECT_NEAR(hit.point.z(), lens_testing::BruteSag(brute, r), 1e-15) << angle << " " << x;
      const double first = BruteCrossing(brute, o, d);
      if (first >= 0) {
        EXPECT_NEAR(hit.t, first, 1e-12) << angle << " " << x;
      }
    }
  }
  EXPECT_GT(hits, 50);
}

TEST(LensSurface, FresnelHitsAreOnTheFoldedSagWithTheUnderlyingNormal) {
  const double pitch = 0.5 * kMm;
  const SurfaceShape shape = Shape(-1 / (40 * kMm), -1, {}, pitch);
  const Surface fresnel(shape);
  const Surface smooth(Shape(-1 / (40 * kMm), -1));
  for (double h : {0.2, 1.3, 4.75, 9.9}) {
    const Eigen::Vector3d o(0, h * kMm, -1 * kMm);
    const SurfaceHit hit = fresnel.Intersect(o, Eigen::Vector3d::UnitZ());
    ASSERT_EQ(hit.status, HitStatus::kHit);
    // The folded sag of the paraboloid z = c r^2 / 2: minus z at the zone's inner edge.
    const double c = -1 / (40 * kMm);
    const double r = h * kMm;
    const double zone_start = std::floor(r / pitch) * pitch;
    EXPECT_NEAR(hit.point.z(), c / 2 * (r * r - zone_start * zone_start), 1e-17) << h;
    EXPECT_NEAR(fresnel.Sag(r), c / 2 * (r * r - zone_start * zone_start), 1e-17) << h;
    EXPECT_LE(hit.point.z(), 0);
    const double groove_depth = c / 2 * ((zone_start + pitch) * (zone_start + pitch) - zone_start * zone_start);
    EXPECT_GE(hit.point.z(), groove_depth);
    EXPECT_LT((hit.normal - smooth.Normal(0, h * kMm)).norm(), 1e-15);
  }
}

TEST(LensSurface, FresnelRayIntoAGrooveWallIsReported) {
  // Zones of 1 mm on a convex R = 20 mm profile: the face of zone 5 climbs to
  // 0.27 mm at its outer edge, zone 6 starts again at 0. A ray that crosses
  // the substrate plane near the edge of zone 5, slanted outward, reaches
  // r = 6 mm while still below zone 5's face: it would enter through the wall.
  const Surface fresnel(Shape(1 / (20 * kMm), 0, {}, 1 * kMm));
  const double a = 60 * M_PI / 180;
  const Eigen::Vector3d d(std::sin(a), 0, std::cos(a));
  const Eigen::Vector3d o = Eigen::Vector3d(5.95 * kMm, 0, 0) - 1 * kMm * d;
  EXPECT_EQ(fresnel.Intersect(o, d).status, HitStatus::kGrooveWall);
  // The same ray slanted inward meets zone 5's face.
  const Eigen::Vector3d inward(-std::sin(a), 0, std::cos(a));
  EXPECT_EQ(fresnel.Intersect(Eigen::Vector3d(5.95 * kMm, 0, 0) - 1 * kMm * inward, inward).status, HitStatus::kHit);
}

}  // namespace
}  // namespace layerlab::lenses
