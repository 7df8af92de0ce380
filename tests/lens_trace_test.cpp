// The exact sequential trace against the independent brute-force tracer of
// lens_brute_force.h (sphere, conic, even asphere, Fresnel; meridional and
// skew rays) to 1e-9 m at an exit plane, and its losses: total internal
// reflection, vignetting; tilt and decentre against closed forms.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "layerlab/lenses/sequential_trace.h"
#include "layerlab/tests/lens_brute_force.h"
#include "layerlab/tests/test_util.h"

namespace layerlab::lenses {
namespace {

using layerlab::testing::ErrorOf;
using lens_testing::AtPlane;
using lens_testing::BruteResult;
using lens_testing::BruteSurface;
using lens_testing::BruteTrace;

constexpr double kMm = 1e-3;
constexpr double kD = 587.5618e-9;

PrescriptionSurface Make(double c, double k, std::vector<double> a, const std::string& material, double thickness,
                         double pitch = 0, double semi_diameter = 12 * kMm) {
  PrescriptionSurface s;
  s.shape.curvature_per_m = c;
  s.shape.conic = k;
  s.shape.even_asphere = std::move(a);
  s.shape.fresnel_pitch_m = pitch;
  s.shape.semi_diameter_m = semi_diameter;
  s.material = material;
  s.thickness_m = thickness;
  return s;
}

// The same prescription for the brute-force tracer (centred; indices at `wavelength`).
std::vector<BruteSurface> BruteOf(const Prescription& p, double wavelength) {
  std::vector<BruteSurface> out;
  double z = 0;
  for (const PrescriptionSurface& s : p.surfaces) {
    out.push_back({z, s.shape.curvature_per_m, s.shape.conic, s.shape.even_asphere, s.shape.fresnel_pitch_m,
                   FindMaterial(s.material).Index(wavelength)});
    z += s.thickness_m;
  }
  return out;
}

// Meridional rays in x and in y, and skew rays (off the meridian, slanted across it).
std::vector<Ray> TestRays() {
  std::vector<Ray> rays;
  for (double h : {-8.0, -3.0, 0.0, 0.5, 4.0, 7.5}) {
    for (const Eigen::Vector3d& dir :
         {Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(0, 0.04, 1), Eigen::Vector3d(0, -0.07, 1)}) {
      rays.push_back({Eigen::Vector3d(0, h * kMm, -20 * kMm), dir.normalized()});
    }
    rays.push_back({Eigen::Vector3d(h * kMm, 0, -20 * kMm), Eigen::Vector3d(0.05, 0, 1).normalized()});
    rays.push_back({Eigen::Vector3d(h * kMm, 2 * kMm, -20 * kMm), Eigen::Vector3d(-0.03, 0.06, 1).normalized()});
    rays.push_back({Eigen::Vector3d(3 * kMm, h * kMm, -15 * kMm), Eigen::Vector3d(0.08, -0.02, 1).normalized()});
  }
  return rays;
}

// Every test ray through `p` against the brute force: the same fate, the same
// point on the plane 80 mm behind the last vertex to 1e-9 m, the same
// direction and optical path length.
void ExpectTracesAgree(const Prescription& p, double wavelength) {
  const LensSystem system(p);
  const SequentialTrace trace(system, wavelength);
  const std::vector<BruteSurface> brute = BruteOf(p, wavelength);
  const double plane = system.vertex_z_m(system.size() - 1) + 80 * kMm;
  int exited = 0;
  for (const Ray& ray : TestRays()) {
    const TraceResult r = trace.Trace(ray);
    const BruteResult b = BruteTrace(brute, trace.index(0), ray.origin, ray.direction);
    const bool vignetted = r.fate == RayFate::kVignetted;
    ASSERT_TRUE(r.exited() || vignetted) << ToString(r.fate) << " at " << r.surface;
    if (vignetted) continue;
    ASSERT_TRUE(b.ok);
    ++exited;
    const Eigen::Vector3d ours = AtPlane(r.exit.origin, r.exit.direction, plane);
    const Eigen::Vector3d theirs = AtPlane(b.point, b.direction, plane);
    EXPECT_LT((ours - theirs).norm(), 1e-9) << "ray from " << ray.origin.transpose();
    EXPECT_LT((r.exit.direction - b.direction).norm(), 1e-11);
    EXPECT_NEAR(r.optical_path_m, b.optical_path, 1e-12);
  }
  EXPECT_GE(exited, 30);
}

TEST(LensTrace, SphericalLensMatchesTheBruteForce) {
  Prescription p;
  p.surfaces = {Make(1 / (50 * kMm), 0, {}, "N-BK7", 6 * kMm), Make(-1 / (40 * kMm), 0, {}, "air", 0)};
  ExpectTracesAgree(p, kD);
  ExpectTracesAgree(p, 486.1327e-9);
}

TEST(LensTrace, ConicLensMatchesTheBruteForce) {
  Prescription p;
  p.surfaces = {Make(1 / (50 * kMm), -0.7, {}, "N-SF11", 6 * kMm), Make(-1 / (40 * kMm), 1.5, {}, "air", 0)};
  ExpectTracesAgree(p, kD);
}

TEST(LensTrace, HyperbolicDoubletMatchesTheBruteForce) {
  Prescription p;
  p.surfaces = {Make(1 / (60 * kMm), -2.5, {}, "N-BK7", 5 * kMm), Make(-1 / (45 * kMm), 0, {}, "N-F2", 2 * kMm),
                Make(-1 / (130 * kMm), 0, {}, "air", 0)};
  ExpectTracesAgree(p, 656.2725e-9);
}

TEST(LensTrace, EvenAsphereMatchesTheBruteForce) {
  Prescription p;
  p.surfaces = {Make(1 / (30 * kMm), -1, {2e3, -1e6}, "PMMA", 8 * kMm), Make(0, 0, {-5e3, 2e6}, "air", 0)};
  ExpectTracesAgree(p, kD);
}

TEST(LensTrace, FresnelLensMatchesTheBruteForce) {
  // A flat PMMA sheet whose back is a Fresnel paraboloid of R = -40 mm in 0.5 mm grooves.
  Prescription p;
  p.surfaces = {Make(0, 0, {}, "PMMA", 2 * kMm), Make(-1 / (40 * kMm), -1, {}, "air", 0, 0.5 * kMm)};
  ExpectTracesAgree(p, kD);
}

TEST(LensTrace, TotalInternalReflectionIsALoss) {
  // Inside N-BK7 toward a flat exit face: the critical angle is asin(1/1.5168) = 41.25 deg.
  Prescription p;
  p.material_before = "N-BK7";
  p.surfaces = {Make(0, 0, {}, "air", 0, 0, 1.0)};
  const LensSystem system(p);
  const double n = FindMaterial("N-BK7").Index(kD);
  auto ray_at = [](double degrees) {
    const double a = degrees * M_PI / 180;
    return Ray{Eigen::Vector3d(0, 0, -1 * kMm), Eigen::Vector3d(0, std::sin(a), std::cos(a))};
  };
  const TraceResult past = TraceRay(system, ray_at(42), kD);
  EXPECT_EQ(past.fate, RayFate::kTotalInternalReflection);
  EXPECT_EQ(past.surface, 0);
  const TraceResult below = TraceRay(system, ray_at(41), kD);
  ASSERT_TRUE(below.exited());
  EXPECT_NEAR(below.exit.direction.y(), n * std::sin(41 * M_PI / 180), 1e-14);  // sin(out) = n sin(in)
}

TEST(LensTrace, OutsideTheClearApertureIsVignettedNotBent) {
  Prescription p;
  p.surfaces = {Make(1 / (50 * kMm), 0, {}, "N-BK7", 6 * kMm, 0, 10 * kMm),
                Make(-1 / (40 * kMm), 0, {}, "air", 0, 0, 5 * kMm)};
  const LensSystem system(p);
  const Ray outside{Eigen::Vector3d(0, 10.01 * kMm, -5 * kMm), Eigen::Vector3d::UnitZ()};
  const TraceResult lost = TraceRay(system, outside, kD);
  EXPECT_EQ(lost.fate, RayFate::kVignetted);
  EXPECT_EQ(lost.surface, 0);
  // Through the first aperture, then outside the second (the ray converges, but not enough).
  const TraceResult second = TraceRay(system, {Eigen::Vector3d(0, 6 * kMm, -5 * kMm), Eigen::Vector3d::UnitZ()}, kD);
  EXPECT_EQ(second.fate, RayFate::kVignetted);
  EXPECT_EQ(second.surface, 1);
  EXPECT_TRUE(TraceRay(system, {Eigen::Vector3d(0, 4.9 * kMm, -5 * kMm), Eigen::Vector3d::UnitZ()}, kD).exited());
}

TEST(LensTrace, TiltedPlateDisplacesByTheClosedForm) {
  // A plane-parallel plate of thickness t tilted by theta shifts a ray, parallel
  // to itself, by t sin(theta) (1 - cos(theta) / sqrt(n^2 - sin^2(theta))).
  const double t = 5 * kMm;
  for (double degrees : {5.0, 20.0, 45.0}) {
    const double theta = degrees * M_PI / 180;
    Prescription p;
    p.surfaces = {Make(0, 0, {}, "N-SF11", t, 0, 1.0), Make(0, 0, {}, "air", 0, 0, 1.0)};
    p.placements = {{0, 1, theta, 0, 0, 0}};
    const LensSystem system(p);
    const double n = FindMaterial("N-SF11").Index(kD);
    const Ray ray{Eigen::Vector3d(0, 1 * kMm, -10 * kMm), Eigen::Vector3d::UnitZ()};
    const TraceResult r = TraceRay(system, ray, kD);
    ASSERT_TRUE(r.exited());
    EXPECT_LT((r.exit.direction - Eigen::Vector3d::UnitZ()).norm(), 1e-15);
    const double s = std::sin(theta);
    const double expected = t * s * (1 - std::cos(theta) / std::sqrt(n * n - s * s));
    EXPECT_NEAR(std::abs(r.exit.origin.y() - 1 * kMm), expected, 1e-15) << degrees << " deg";
    // Tilted toward -y (about x), the plate moves the ray toward -y.
    EXPECT_LT(r.exit.origin.y(), 1 * kMm);
  }
}

TEST(LensTrace, DecentredPlateChangesNothingAndDecentredLensDeflects) {
  Prescription plate;
  plate.surfaces = {Make(0, 0, {}, "N-BK7", 3 * kMm), Make(0, 0, {}, "air", 0)};
  Prescription moved = plate;
  moved.placements = {{0, 1, 0, 0, 1.5 * kMm, -0.7 * kMm}};
  const Ray ray{Eigen::Vector3d(0.5 * kMm, 1 * kMm, -10 * kMm), Eigen::Vector3d(0.03, -0.02, 1).normalized()};
  const TraceResult a = TraceRay(LensSystem(plate), ray, kD);
  const TraceResult b = TraceRay(LensSystem(moved), ray, kD);
  ASSERT_TRUE(a.exited() && b.exited());
  EXPECT_LT((a.exit.direction - b.exit.direction).norm(), 1e-15);
  EXPECT_LT((a.exit.origin - b.exit.origin).norm(), 1e-15);
  // A lens decentred by e sends the axial ray through its point at height -e:
  // the same exit ray as the centred lens gives the ray at height -e, moved by e.
  Prescription lens;
  lens.surfaces = {Make(1 / (50 * kMm), 0, {}, "N-BK7", 6 * kMm), Make(-1 / (40 * kMm), 0, {}, "air", 0)};
  Prescription shifted = lens;
  shifted.placements = {{0, 1, 0, 0, 0, 2 * kMm}};
  const TraceResult axial =
      TraceRay(LensSystem(shifted), {Eigen::Vector3d(0, 0, -5 * kMm), Eigen::Vector3d::UnitZ()}, kD);
  const TraceResult below =
      TraceRay(LensSystem(lens), {Eigen::Vector3d(0, -2 * kMm, -5 * kMm), Eigen::Vector3d::UnitZ()}, kD);
  ASSERT_TRUE(axial.exited() && below.exited());
  EXPECT_LT((axial.exit.direction - below.exit.direction).norm(), 1e-15);
  EXPECT_LT((axial.exit.origin - (below.exit.origin + Eigen::Vector3d(0, 2 * kMm, 0))).norm(), 1e-15);
}

TEST(LensTrace, TiltedLensMatchesTheCentredLensInItsOwnFrame) {
  // Tilting the lens by a about x through its first vertex equals tilting the
  // ray by -a about the same point (a rigid rotation of the whole picture).
  const double a = 3 * M_PI / 180;
  Prescription lens;
  lens.surfaces = {Make(1 / (50 * kMm), 0, {}, "N-BK7", 6 * kMm), Make(-1 / (40 * kMm), 0, {}, "air", 0)};
  Prescription tilted = lens;
  tilted.placements = {{0, 1, a, 0, 0, 0}};
  const Eigen::Matrix3d rotation = Eigen::AngleAxisd(a, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const Ray ray{Eigen::Vector3d(1 * kMm, 2 * kMm, -10 * kMm), Eigen::Vector3d(0.01, 0.02, 1).normalized()};
  const Ray in_lens_frame{rotation.transpose() * ray.origin, rotation.transpose() * ray.direction};
  const TraceResult r = TraceRay(LensSystem(tilted), ray, kD);
  const TraceResult c = TraceRay(LensSystem(lens), in_lens_frame, kD);
  ASSERT_TRUE(r.exited() && c.exited());
  EXPECT_LT((r.exit.origin - rotation * c.exit.origin).norm(), 1e-15);
  EXPECT_LT((r.exit.direction - rotation * c.exit.direction).norm(), 1e-15);
  EXPECT_NEAR(r.optical_path_m, c.optical_path_m, 1e-15);
}

TEST(LensTrace, BadRaysAreLostNotNaN) {
  Prescription p;
  p.surfaces = {Make(1 / (50 * kMm), -1, {2e3}, "N-BK7", 6 * kMm), Make(-1 / (40 * kMm), 0, {}, "air", 0)};
  const LensSystem system(p);
  const TraceResult nan_ray = TraceRay(system, {Eigen::Vector3d(NAN, 0, -1 * kMm), Eigen::Vector3d::UnitZ()}, kD);
  EXPECT_EQ(nan_ray.fate, RayFate::kMissed);
  const TraceResult sideways = TraceRay(system, {Eigen::Vector3d(0, 0, -1 * kMm), Eigen::Vector3d::UnitX()}, kD);
  EXPECT_EQ(sideways.fate, RayFate::kMissed);
  const TraceResult backwards = TraceRay(system, {Eigen::Vector3d(0, 0, -1 * kMm), -Eigen::Vector3d::UnitZ()}, kD);
  EXPECT_EQ(backwards.fate, RayFate::kMissed);
}

TEST(LensTrace, BadPrescriptionsNameTheField) {
  Prescription p;
  p.surfaces = {Make(1 / (50 * kMm), 0, {}, "BK7", 6 * kMm), Make(0, 0, {}, "air", 0)};
  const Location where{"lens.json", "/elements/2/prescription"};
  EXPECT_EQ(ErrorOf([&] { LensSystem s(p, where); }),
            "lens.json: /elements/2/prescription/surfaces/0/material: unknown material \"BK7\" (the catalogue knows "
            "air, N-BK7, N-SF11, N-F2, N-LAK22, N-SF5, N-BAF10, SF5, PMMA, PC, E48R)");
  p.surfaces[0].material = "N-BK7";
  p.surfaces[1].shape.semi_diameter_m = 0;
  EXPECT_EQ(ErrorOf([&] { LensSystem s(p, where); }),
            "lens.json: /elements/2/prescription/surfaces/1/semi_diameter_m: expected a semi-diameter > 0");
  p.surfaces[1].shape.semi_diameter_m = 0.1;  // beyond the 50 mm sphere's edge? no: the plane has no edge
  p.surfaces[0].shape.semi_diameter_m = 0.06;
  EXPECT_EQ(ErrorOf([&] { LensSystem s(p, where); }),
            "lens.json: /elements/2/prescription/surfaces/0/semi_diameter_m: the clear aperture reaches beyond the "
            "conic's edge, where its sag is undefined");
  p.surfaces[0].shape.semi_diameter_m = 0.01;
  p.placements = {{0, 2, 0.1, 0, 0, 0}};
  EXPECT_EQ(ErrorOf([&] { LensSystem s(p, where); }),
            "lens.json: /elements/2/prescription/placements/0: expected surfaces first_surface <= last_surface within "
            "0 to 1");
  p.placements = {};
  EXPECT_EQ(ErrorOf([&] { SequentialTrace t(LensSystem(p), 290e-9); }),
            "N-BK7: 290 nm lies outside the range of its dispersion formula, 300 nm to 2500 nm (SCHOTT optical glass "
            "catalogue, Zemax edition 2017-01-20b)");
}

}  // namespace
}  // namespace layerlab::lenses
