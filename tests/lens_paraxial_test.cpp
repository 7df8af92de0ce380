// The paraxial properties two ways (ray-transfer matrices; the exact trace in
// the paraxial limit) against each other, the thick-lens formula and the
// published focal lengths of catalogue lenses.
#include <cmath>

#include <gtest/gtest.h>

#include "layerlab/lenses/paraxial.h"
#include "layerlab/tests/test_util.h"

namespace layerlab::lenses {
namespace {

using layerlab::testing::Close;
using layerlab::testing::ErrorOf;

constexpr double kMm = 1e-3;
constexpr double kD = 587.5618e-9;
constexpr double kHeNe = 632.8e-9;

PrescriptionSurface Make(double radius_m, const std::string& material, double thickness_m, double k = 0,
                         std::vector<double> a = {}, double pitch = 0) {
  PrescriptionSurface s;
  s.shape.curvature_per_m = radius_m == 0 ? 0 : 1 / radius_m;
  s.shape.conic = k;
  s.shape.even_asphere = std::move(a);
  s.shape.fresnel_pitch_m = pitch;
  s.shape.semi_diameter_m = 12.7 * kMm;
  s.material = material;
  s.thickness_m = thickness_m;
  return s;
}

LensSystem Singlet(double r1, double r2, double thickness, const std::string& glass) {
  Prescription p;
  p.surfaces = {Make(r1, glass, thickness), Make(r2, "air", 0)};
  return LensSystem(p);
}

void ExpectSame(const ParaxialProperties& a, const ParaxialProperties& b, double rel) {
  const double scale = std::abs(a.efl_m);
  EXPECT_TRUE(Close(a.efl_m, b.efl_m, rel));
  EXPECT_TRUE(Close(a.bfl_m, b.bfl_m, 0, rel * scale));
  EXPECT_TRUE(Close(a.ffl_m, b.ffl_m, 0, rel * scale));
  EXPECT_TRUE(Close(a.front_principal_plane_m, b.front_principal_plane_m, 0, rel * scale));
  EXPECT_TRUE(Close(a.back_principal_plane_m, b.back_principal_plane_m, 0, rel * scale));
}

ParaxialProperties FromTrace(const LensSystem& s, double wavelength) {
  return PropertiesOf(TransferFromExactTrace(s, wavelength), s.material_before().Index(wavelength),
                      s.material_after(s.size() - 1).Index(wavelength));
}

TEST(LensParaxial, ThickLensFormula) {
  // Biconvex N-BK7, R1 = 50 mm, R2 = -40 mm, 6 mm thick, in air:
  //   1/f = (n - 1) (1/R1 - 1/R2 + (n - 1) d / (n R1 R2)),
  //   BFL = f (1 - (n - 1) d / (n R1)),  FFL = f (1 + (n - 1) d / (n R2)),
  //   principal planes h1 = -f (n - 1) d / (n R2) from the first vertex, h2 = -f (n - 1) d / (n R1) from the last.
  const double r1 = 50 * kMm, r2 = -40 * kMm, d = 6 * kMm;
  const LensSystem lens = Singlet(r1, r2, d, "N-BK7");
  for (double wavelength : {kD, 486.1327e-9, 656.2725e-9}) {
    const double n = FindMaterial("N-BK7").Index(wavelength);
    const double f = 1 / ((n - 1) * (1 / r1 - 1 / r2 + (n - 1) * d / (n * r1 * r2)));
    ParaxialProperties formula;
    formula.efl_m = f;
    formula.bfl_m = f * (1 - (n - 1) * d / (n * r1));
    formula.ffl_m = f * (1 + (n - 1) * d / (n * r2));
    formula.front_principal_plane_m = -f * (n - 1) * d / (n * r2);
    formula.back_principal_plane_m = -f * (n - 1) * d / (n * r1);
    ExpectSame(ParaxialAt(lens, wavelength), formula, 1e-12);
    ExpectSame(FromTrace(lens, wavelength), formula, 1e-9);
  }
}

TEST(LensParaxial, ExactTraceLimitEqualsTheMatricesForEveryKindOfSurface) {
  // Conics, aspheric terms and Fresnel folds leave the paraxial power to the
  // vertex curvature: the traced limit sees them vanish.
  Prescription p;
  p.surfaces = {Make(60 * kMm, "N-LAK22", 5 * kMm, -2.5, {4e3, -1e6}), Make(-45 * kMm, "N-SF11", 2 * kMm, 0.7),
                Make(-130 * kMm, "air", 10 * kMm), Make(0, "PMMA", 2 * kMm),
                Make(-40 * kMm, "air", 0, -1, {}, 0.5 * kMm)};
  const LensSystem system(p);
  for (double wavelength : {kD, 450e-9, 1000e-9}) {
    ExpectSame(FromTrace(system, wavelength), ParaxialAt(system, wavelength), 1e-9);
  }
  // A negative meniscus of polycarbonate in E48R "immersion" on both sides.
  Prescription q;
  q.material_before = "E48R";
  q.surfaces = {Make(-30 * kMm, "PC", 3 * kMm), Make(-80 * kMm, "E48R", 0)};
  const LensSystem meniscus(q);
  ExpectSame(FromTrace(meniscus, kD), ParaxialAt(meniscus, kD), 1e-9);
  EXPECT_LT(ParaxialAt(meniscus, kD).efl_m, 0);
}

// Thorlabs LA1608 and LA1509, N-BK7 plano-convex, curved side toward the
// collimated beam (thorlabs.com, N-BK7 plano-convex lenses): f 75.0 mm, R 38.6
// mm, tc 4.1 mm, BFL 72.3 mm; f 100.0 mm, R 51.5 mm, tc 3.6 mm, BFL 97.6 mm.
// Those f hold at 632.8 nm (the page's "587.6 nm or 633 nm"): at 587.6 nm
// R / (n - 1) gives 74.69 and 99.65 mm. The radius is rounded to 0.1 mm, which
// moves f by up to 0.1 mm; f and BFL are rounded to 0.1 mm.
TEST(LensParaxial, ThorlabsPlanoConvexLenses) {
  struct Part {
    const char* name;
    double radius_mm, thickness_mm, f_mm, bfl_mm;
  };
  for (const Part& part : {Part{"LA1608", 38.6, 4.1, 75.0, 72.3}, Part{"LA1509", 51.5, 3.6, 100.0, 97.6}}) {
    const LensSystem lens = Singlet(part.radius_mm * kMm, 0, part.thickness_mm * kMm, "N-BK7");
    const ParaxialProperties p = ParaxialAt(lens, kHeNe);
    EXPECT_NEAR(p.efl_m / kMm, part.f_mm, 0.15) << part.name;
    EXPECT_NEAR(p.bfl_m / kMm, part.bfl_mm, 0.15) << part.name;
    const ParaxialProperties traced = FromTrace(lens, kHeNe);
    EXPECT_NEAR(traced.efl_m / kMm, part.f_mm, 0.15) << part.name;
    EXPECT_NEAR(traced.bfl_m / kMm, part.bfl_mm, 0.15) << part.name;
  }
}

// Thorlabs AC254-100-A, N-BK7 / SF5 achromat, as in Thorlabs' own Zemax file
// (R1 62.75, R2 -45.71, R3 -128.23 mm, tc 4.0 and 2.5 mm): the spec sheet's
// focal length 100.1 mm at 587.6 nm (rounded to 0.1 mm). Its BFL (97.1 mm) is
// not checked: the paraxial BFL is 97.16 mm, the sheet's value is presumably
// a best focus, not the paraxial one.
TEST(LensParaxial, ThorlabsAchromat) {
  Prescription p;
  p.surfaces = {Make(62.75 * kMm, "N-BK7", 4.0 * kMm), Make(-45.71 * kMm, "SF5", 2.5 * kMm),
                Make(-128.23 * kMm, "air", 0)};
  const LensSystem doublet(p);
  EXPECT_NEAR(ParaxialAt(doublet, kD).efl_m / kMm, 100.1, 0.05);
  EXPECT_NEAR(FromTrace(doublet, kD).efl_m / kMm, 100.1, 0.05);
  // An achromat: its F and C focal lengths differ by less than a tenth of the
  // f / vd = 1.56 mm of an N-BK7 singlet of the same focal length.
  const double spread = ParaxialAt(doublet, 486.1327e-9).efl_m - ParaxialAt(doublet, 656.2725e-9).efl_m;
  EXPECT_LT(std::abs(spread), 0.156 * kMm);
}

TEST(LensParaxial, TiltedSystemsAreRefused) {
  Prescription p;
  p.surfaces = {Make(50 * kMm, "N-BK7", 5 * kMm), Make(0, "air", 0)};
  p.placements = {{0, 1, 0.01, 0, 0, 0}};
  const LensSystem tilted(p);
  EXPECT_EQ(ErrorOf([&] { ParaxialAt(tilted, kD); }),
            "paraxial properties need a centred system: a placement tilts or decentres a group");
  EXPECT_EQ(ErrorOf([&] { TransferFromExactTrace(tilted, kD); }),
            "paraxial properties need a centred system: a placement tilts or decentres a group");
}

}  // namespace
}  // namespace layerlab::lenses
