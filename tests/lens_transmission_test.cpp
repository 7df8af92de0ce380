// Surface and bulk transmission in the exact trace against independent
// computations: the Fresnel equations' sine and tangent forms and amplitude
// transmission coefficients, Brewster's angle, the Airy sum of a single film
// and its quarter-wave closed form, SCHOTT's published internal transmittances,
// and a plano-convex singlet and an oblique slab traced by hand.
#include <cmath>
#include <complex>
#include <numbers>
#include <string>

#include <gtest/gtest.h>

#include "layerlab/lenses/glass_absorption.h"
#include "layerlab/lenses/sequential_trace.h"
#include "layerlab/lenses/surface_transmission.h"
#include "layerlab/tests/test_util.h"

namespace layerlab::lenses {
namespace {

using layerlab::testing::ErrorOf;

constexpr double kMm = 1e-3;
constexpr double kD = 587.5618e-9;
constexpr double kNd = 1.51680;  // N-BK7's published nd (SCHOTT data sheet)
constexpr double kPi = std::numbers::pi;

// Snell's law for the angle of refraction (radians).
double Refracted(double n1, double n2, double theta_i) { return std::asin(n1 / n2 * std::sin(theta_i)); }

// A flat slab of `material`, 10 mm thick.
Prescription SlabOf(const std::string& material) {
  Prescription p;
  p.surfaces.resize(2);
  p.surfaces[0].material = material;
  p.surfaces[0].thickness_m = 10e-3;
  return p;
}

TEST(LensTransmission, NormalIncidenceOnNBk7) {
  // Hand-derived: ((1.5168 - 1) / (1.5168 + 1))^2 = (0.5168 / 2.5168)^2 = 0.042165 (4.22 %).
  const Reflectance r = UncoatedReflectance(1.0, kNd, 1.0);
  EXPECT_NEAR(r.s, 0.042165, 5e-7);
  EXPECT_NEAR(r.p, 0.042165, 5e-7);
  EXPECT_NEAR(UncoatedReflectance(kNd, 1.0, 1.0).Unpolarized(), 0.042165, 5e-7);  // the same from inside
  EXPECT_NEAR(SurfaceTransmittance(Coating{}, 1.0, kNd, 1.0, kD), 1 - 0.042165, 5e-7);
}

TEST(LensTransmission, BrewsterAngleReflectsNoP) {
  for (const auto& [n1, n2] : {std::pair{1.0, kNd}, std::pair{kNd, 1.0}, std::pair{1.5168, 1.7847}}) {
    const double theta_b = std::atan(n2 / n1);  // tan theta_B = n2 / n1
    const double theta_t = Refracted(n1, n2, theta_b);
    const Reflectance r = UncoatedReflectance(n1, n2, std::cos(theta_b));
    EXPECT_LT(r.p, 1e-20) << n1 << " -> " << n2;
    // s by the sine form, sin^2(i - t) / sin^2(i + t), with i + t = 90 deg at Brewster's angle.
    EXPECT_NEAR(theta_b + theta_t, kPi / 2, 1e-12);
    EXPECT_NEAR(r.s, std::pow(std::sin(theta_b - theta_t), 2), 1e-14) << n1 << " -> " << n2;
  }
}

// Power transmittances from the amplitude coefficients t = 2 n1 cos_i / (...),
// T = (n2 cos_t) / (n1 cos_i) t^2, and reflectances from the sine and tangent
// forms: R + T = 1 for s and p, from both sides, at every angle short of TIR.
TEST(LensTransmission, ReflectedPlusTransmittedIsOnePerInterface) {
  for (const auto& [n1, n2] : {std::pair{1.0, kNd}, std::pair{kNd, 1.0}, std::pair{1.62, 1.78}}) {
    for (double deg = 1; deg < 89.5; deg += 2.5) {
      const double i = deg * kPi / 180;
      if (n1 / n2 * std::sin(i) >= 1) continue;
      const double t = Refracted(n1, n2, i);
      const double ci = std::cos(i), ct = std::cos(t);
      const double ts = 2 * n1 * ci / (n1 * ci + n2 * ct);
      const double tp = 2 * n1 * ci / (n2 * ci + n1 * ct);
      const double power_ratio = (n2 * ct) / (n1 * ci);
      const Reflectance r = UncoatedReflectance(n1, n2, ci);
      EXPECT_NEAR(r.s + power_ratio * ts * ts, 1.0, 1e-13) << n1 << " -> " << n2 << " at " << deg;
      EXPECT_NEAR(r.p + power_ratio * tp * tp, 1.0, 1e-13) << n1 << " -> " << n2 << " at " << deg;
      EXPECT_NEAR(r.s, std::pow(std::sin(i - t) / std::sin(i + t), 2), 1e-12);
      EXPECT_NEAR(r.p, std::pow(std::tan(i - t) / std::tan(i + t), 2), 1e-12);
    }
  }
  EXPECT_EQ(UncoatedReflectance(kNd, 1.0, std::cos(45 * kPi / 180)).s, 1.0);  // past the critical angle
}

// |r|^2 of a single film (index nc, thickness d) between n1 and n2 by the Airy
// sum of its two interfaces' amplitude coefficients (not the characteristic matrix).
Reflectance AiryFilm(double n1, double nc, double n2, double d, double theta1, double wavelength) {
  using C = std::complex<double>;
  const double invariant = n1 * std::sin(theta1);
  const C c1(std::cos(theta1));
  const C cc = std::sqrt(C(1 - std::pow(invariant / nc, 2)));
  const C c2 = std::sqrt(C(1 - std::pow(invariant / n2, 2)));
  auto rs = [](double na, C ca, double nb, C cb) { return (na * ca - nb * cb) / (na * ca + nb * cb); };
  auto rp = [](double na, C ca, double nb, C cb) { return (nb * ca - na * cb) / (nb * ca + na * cb); };
  const C phase = std::exp(C(0, 2) * (2 * kPi * nc * d * cc / wavelength));
  auto airy = [&](C r01, C r12) { return std::norm((r01 + r12 * phase) / (1.0 + r01 * r12 * phase)); };
  return {airy(rs(n1, c1, nc, cc), rs(nc, cc, n2, c2)), airy(rp(n1, c1, nc, cc), rp(nc, cc, n2, c2))};
}

TEST(LensTransmission, QuarterWaveMgF2AtItsDesignWavelength) {
  const double design = 550e-9, nc = 1.38;
  const double ns = FindMaterial("N-BK7").Index(design);
  const double closed = std::pow((1.0 * ns - nc * nc) / (1.0 * ns + nc * nc), 2);  // 0.0126 for N-BK7
  EXPECT_NEAR(closed, 0.0126, 2e-4);
  const Reflectance r = QuarterWaveReflectance(1.0, ns, 1.0, nc, design, design);
  EXPECT_NEAR(r.s, closed, 1e-14);
  EXPECT_NEAR(r.p, closed, 1e-14);
  EXPECT_NEAR(QuarterWaveReflectance(ns, 1.0, 1.0, nc, design, design).Unpolarized(), closed, 1e-14);
  const Coating mgf2{Coating::Kind::kQuarterWave, nc, design, 0.0};
  EXPECT_NEAR(SurfaceTransmittance(mgf2, 1.0, ns, 1.0, design), 1 - closed, 1e-14);
}

TEST(LensTransmission, QuarterWaveAtAnAngleMatchesTheAirySum) {
  const double design = 550e-9, nc = 1.38, d = design / (4 * nc);
  for (double wavelength : {450e-9, 550e-9, 650e-9}) {
    const double ns = FindMaterial("N-BK7").Index(wavelength);
    for (double deg : {0.0, 15.0, 30.0, 45.0, 60.0, 75.0}) {
      const double theta = deg * kPi / 180;
      const Reflectance ours = QuarterWaveReflectance(1.0, ns, std::cos(theta), nc, design, wavelength);
      const Reflectance airy = AiryFilm(1.0, nc, ns, d, theta, wavelength);
      EXPECT_NEAR(ours.s, airy.s, 1e-13) << wavelength << " at " << deg;
      EXPECT_NEAR(ours.p, airy.p, 1e-13) << wavelength << " at " << deg;
      // From the glass side, at the angle that refracts into the same air angle.
      const double inside = Refracted(1.0, ns, theta);
      const Reflectance back = QuarterWaveReflectance(ns, 1.0, std::cos(inside), nc, design, wavelength);
      EXPECT_NEAR(back.s, airy.s, 1e-13) << wavelength << " at " << deg;
      EXPECT_NEAR(back.p, airy.p, 1e-13) << wavelength << " at " << deg;
    }
  }
  // Between two glasses past the film's own critical angle (evanescent in the film).
  const double theta = 70 * kPi / 180;  // 1.62 sin 70 deg = 1.52 > 1.38
  const Reflectance ours = QuarterWaveReflectance(1.62, 1.78, std::cos(theta), nc, design, design);
  const Reflectance airy = AiryFilm(1.62, nc, 1.78, d, theta, design);
  EXPECT_NEAR(ours.s, airy.s, 1e-12);
  EXPECT_NEAR(ours.p, airy.p, 1e-12);
}

TEST(LensTransmission, StatedReflectance) {
  const Coating thorlabs_a{Coating::Kind::kStatedReflectance, 0, 0, 0.005};  // "Ravg < 0.5 %, 400-700 nm"
  EXPECT_EQ(SurfaceTransmittance(thorlabs_a, 1.0, kNd, std::cos(0.5), kD), 0.995);
}

TEST(LensTransmission, PublishedInternalTransmittanceOfNBk7) {
  const Material& bk7 = FindMaterial("N-BK7");
  // SCHOTT N-BK7 data sheet, tau_i at 400 nm: 0.992 for 25 mm, 0.997 for 10 mm
  // (3 decimals); at 2325 nm 0.560 and 0.793.
  EXPECT_NEAR(InternalTransmittance(bk7, 400e-9, 25 * kMm), 0.992, 1e-12);
  EXPECT_NEAR(InternalTransmittance(bk7, 400e-9, 10 * kMm), 0.997, 5e-4);
  EXPECT_NEAR(InternalTransmittance(bk7, 2325e-9, 25 * kMm), 0.560, 1e-12);
  EXPECT_NEAR(InternalTransmittance(bk7, 2325e-9, 10 * kMm), 0.793, 5e-4);
  // Beer-Lambert: 20 mm transmits the square of 10 mm, 0 mm everything.
  for (double wavelength : {400e-9, 587.6e-9, 2325e-9}) {
    const double ten = InternalTransmittance(bk7, wavelength, 10 * kMm);
    EXPECT_NEAR(InternalTransmittance(bk7, wavelength, 20 * kMm), ten * ten, 1e-15);
    EXPECT_EQ(InternalTransmittance(bk7, wavelength, 0.0), 1.0);
  }
  // Between the listed 580 nm (0.995) and 620 nm (0.994): ln tau linear in wavelength.
  const double f = (587.6 - 580) / (620 - 580);
  EXPECT_NEAR(InternalTransmittance(bk7, 587.6e-9, 25 * kMm), std::exp((1 - f) * std::log(0.995) + f * std::log(0.994)),
              1e-14);
}

// The 10 mm column of the SCHOTT N-SF5 data sheet (as tabulated by the jocular
// ray tracer's N-SF5 material, 10 mm samples), against the catalogue's 25 mm
// table scaled to 10 mm: within the data sheet's rounding at every wavelength.
TEST(LensTransmission, NSf5MatchesItsDataSheetAt10Mm) {
  struct Point {
    double nm, tau_10mm;
  };
  constexpr Point kSheet[] = {{370, 0.276},  {380, 0.642},  {390, 0.826},  {400, 0.905}, {405, 0.928},
                              {420, 0.963},  {436, 0.973},  {460, 0.982},  {500, 0.990}, {546, 0.995},
                              {580, 0.996},  {620, 0.995},  {660, 0.995},  {700, 0.996}, {1060, 0.998},
                              {1530, 0.990}, {1970, 0.950}, {2325, 0.831}, {2500, 0.758}};
  const Material& sf5 = FindMaterial("N-SF5");
  for (const Point& p : kSheet) {
    EXPECT_NEAR(InternalTransmittance(sf5, p.nm * 1e-9, 10 * kMm), p.tau_10mm, 5.01e-4) << p.nm << " nm";
  }
}

TEST(LensTransmission, MaterialsWithoutDataSaySo) {
  for (const char* name : {"PMMA", "PC", "E48R", "air"}) {
    const Material& m = FindMaterial(name);
    EXPECT_FALSE(HasAbsorptionData(m)) << name;
    EXPECT_EQ(AbsorptionPerMeter(m, 550e-9), 0.0) << name;
    EXPECT_NE(AbsorptionSource(m).find("absorption not modelled"), std::string::npos) << name;
  }
  for (const char* name : {"N-BK7", "N-SF11", "N-F2", "N-LAK22", "N-SF5", "N-BAF10", "SF5"}) {
    EXPECT_TRUE(HasAbsorptionData(FindMaterial(name))) << name;
  }
  EXPECT_EQ(ErrorOf([] { AbsorptionPerMeter(FindMaterial("N-SF11"), 360e-9); }),
            "N-SF11: 360 nm lies outside its internal transmittance table, 370 nm to 2500 nm (SCHOTT Zemax "
            "catalogue 2017-01-20b, internal transmittance of 25 mm (via refractiveindex.info))");
}

// Each table spans its glass's dispersion formula range, so that a trace valid
// for the indices never fails on the absorption (the trace evaluates both).
TEST(LensTransmission, AbsorptionTablesCoverTheDispersionRanges) {
  for (const std::string& name : MaterialNames()) {
    const Material& m = FindMaterial(name);
    if (!HasAbsorptionData(m)) continue;
    EXPECT_EQ(ErrorOf([&] { AbsorptionPerMeter(m, m.min_wavelength_m); }), "no error") << name;
    EXPECT_EQ(ErrorOf([&] { AbsorptionPerMeter(m, m.max_wavelength_m); }), "no error") << name;
    EXPECT_EQ(ErrorOf([&] { SequentialTrace(LensSystem(SlabOf(name)), m.min_wavelength_m); }), "no error");
  }
}

// Thorlabs LA1608 (N-BK7, R 38.6 mm, tc 4.1 mm), curved side first.
Prescription La1608(const Coating& coating = {}) {
  Prescription p;
  p.surfaces.resize(2);
  p.surfaces[0].shape.curvature_per_m = 1 / (38.6 * kMm);
  p.surfaces[0].shape.semi_diameter_m = 12.7 * kMm;
  p.surfaces[0].material = "N-BK7";
  p.surfaces[0].thickness_m = 4.1 * kMm;
  p.surfaces[0].coating = coating;
  p.surfaces[1].shape.semi_diameter_m = 12.7 * kMm;
  p.surfaces[1].coating = coating;
  return p;
}

// N-BK7's tau for 25 mm at 587.6 nm, from the published 580 and 620 nm values.
double Bk7Tau25At587() {
  const double f = (587.6 - 580) / (620 - 580);
  return std::exp((1 - f) * std::log(0.995) + f * std::log(0.994));
}

TEST(LensTransmission, UncoatedPlanoConvexOnAxis) {
  const double n = FindMaterial("N-BK7").Index(587.6e-9);
  const double r = std::pow((n - 1) / (n + 1), 2);  // both surfaces at normal incidence on the axis
  const double surfaces = (1 - r) * (1 - r);
  EXPECT_NEAR(surfaces, 0.917, 5e-4);
  const double bulk = std::pow(Bk7Tau25At587(), 4.1 / 25);  // 0.99918
  const LensSystem lens(La1608());
  EXPECT_NEAR(AxialTransmittance(lens, 587.6e-9), surfaces * bulk, 1e-13);
  EXPECT_NEAR(TraceRay(lens, {Eigen::Vector3d(0, 0, -5 * kMm), Eigen::Vector3d::UnitZ()}, 587.6e-9).transmittance,
              surfaces * bulk, 1e-13);
}

TEST(LensTransmission, CoatedPlanoConvexOnAxis) {
  const double design = 550e-9, nc = 1.38;
  const double n = FindMaterial("N-BK7").Index(design);
  const double r = std::pow((n - nc * nc) / (n + nc * nc), 2);
  const double f = (550.0 - 546) / (580 - 546);  // between the listed 546 nm (0.996) and 580 nm (0.995)
  const double bulk = std::pow(std::exp((1 - f) * std::log(0.996) + f * std::log(0.995)), 4.1 / 25);
  const LensSystem lens(La1608({Coating::Kind::kQuarterWave, nc, design, 0}));
  EXPECT_NEAR(AxialTransmittance(lens, design), (1 - r) * (1 - r) * bulk, 1e-13);
  const LensSystem thorlabs_a(La1608({Coating::Kind::kStatedReflectance, 0, 0, 0.005}));
  EXPECT_NEAR(AxialTransmittance(thorlabs_a, design), 0.995 * 0.995 * bulk, 1e-13);
}

// A 20 mm N-BK7 slab met at 30 deg: Fresnel at both faces (the exit angle
// inside is the entry's refracted one) and exp(-alpha L) over the slanted path
// L = 20 mm / cos t, not the axial thickness and not the optical path.
TEST(LensTransmission, ObliqueSlabCountsTheGeometricPathInside) {
  Prescription p;
  p.surfaces.resize(2);
  p.surfaces[0].material = "N-BK7";
  p.surfaces[0].thickness_m = 20 * kMm;
  const LensSystem slab(p);
  const double wavelength = 400e-9, i = 30 * kPi / 180;
  const double n = FindMaterial("N-BK7").Index(wavelength);
  const double t = Refracted(1.0, n, i);
  auto unpolarized = [](double a, double b) {
    return 1 - 0.5 * (std::pow(std::sin(a - b) / std::sin(a + b), 2) + std::pow(std::tan(a - b) / std::tan(a + b), 2));
  };
  const double bulk = std::pow(0.992, (20 / std::cos(t)) / 25);  // 400 nm: 0.992 for 25 mm
  const double expected = unpolarized(i, t) * bulk * unpolarized(t, i);
  const SequentialTrace trace(slab, wavelength);
  const TraceResult r =
      trace.Trace({Eigen::Vector3d(0, -5 * kMm, -5 * kMm), Eigen::Vector3d(0, std::sin(i), std::cos(i))});
  ASSERT_TRUE(r.exited());
  EXPECT_NEAR(r.transmittance, expected, 1e-13);
}

TEST(LensTransmission, LostRaysCarryNothing) {
  Prescription p = La1608();
  const LensSystem lens(p);
  const TraceResult r = TraceRay(lens, {Eigen::Vector3d(0, 20 * kMm, -5 * kMm), Eigen::Vector3d::UnitZ()}, kD);
  EXPECT_EQ(r.fate, RayFate::kVignetted);
  EXPECT_EQ(r.transmittance, 0.0);
}

TEST(LensTransmission, AxialRayLostIsAnError) {
  Prescription p;
  p.surfaces.resize(2);
  p.surfaces[0].shape.curvature_per_m = 1 / (5 * kMm);  // a 5 mm ball's cap, decentred 10 mm off the axis
  p.surfaces[0].shape.semi_diameter_m = 4 * kMm;
  p.surfaces[0].material = "N-BK7";
  p.surfaces[0].thickness_m = 2 * kMm;
  p.placements = {{0, 1, 0, 0, 10 * kMm, 0}};
  const LensSystem off_axis(p);
  EXPECT_EQ(ErrorOf([&] { AxialTransmittance(off_axis, 550e-9); }),
            "the axial ray at 550 nm is lost at surface 0 (missed the surface)");
}

TEST(LensTransmission, BadCoatingsAreRefused) {
  Prescription p = La1608({Coating::Kind::kQuarterWave, 0.9, 550e-9, 0});
  EXPECT_EQ(ErrorOf([&] {
              LensSystem lens(p, Location{"lens.json", ""});
            }),
            "lens.json: /surfaces/0/coating/index: expected the film's refractive index, finite and >= 1 (MgF2: 1.38)");
  p = La1608({Coating::Kind::kQuarterWave, 1.38, 0, 0});
  EXPECT_EQ(ErrorOf([&] {
              LensSystem lens(p, Location{"lens.json", ""});
            }),
            "lens.json: /surfaces/0/coating/design_wavelength_m: expected a design wavelength > 0 (meters)");
  p = La1608({Coating::Kind::kStatedReflectance, 0, 0, 1.0});
  EXPECT_EQ(ErrorOf([&] {
              LensSystem lens(p, Location{"lens.json", ""});
            }),
            "lens.json: /surfaces/0/coating/reflectance: expected a reflectance in [0, 1) (0.005: 0.5 %)");
}

}  // namespace
}  // namespace layerlab::lenses
