// The .zmx subset (lenses/zmx_format.h): the shipped files read number by
// number against the parts' published data; their focal lengths against
// Thorlabs' values and against the Gullstrand combination of the surfaces
// written here; the round trip; lens units; encodings; and the refusals,
// each naming its line.
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "layerlab/lenses/paraxial.h"
#include "layerlab/lenses/zmx_format.h"
#include "layerlab/tests/test_util.h"

namespace layerlab::lenses {
namespace {

using layerlab::testing::Close;
using layerlab::testing::ErrorOf;
using layerlab::testing::ExamplePath;

constexpr double kMm = 1e-3;
constexpr double kD = 587.5618e-9;
constexpr double kHeNe = 632.8e-9;

std::string ReadBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream bytes;
  bytes << in.rdbuf();
  EXPECT_TRUE(in.good() || in.eof()) << path;
  return bytes.str();
}

Prescription ReadExampleLens(const std::string& name) {
  return ReadZmx(ReadBytes(ExamplePath("lenses/" + name)), name);
}

// Field by field, exactly.
void ExpectSame(const Prescription& a, const Prescription& b) {
  EXPECT_EQ(a.material_before, b.material_before);
  EXPECT_EQ(a.stop_surface, b.stop_surface);
  EXPECT_EQ(a.placements.size(), b.placements.size());
  ASSERT_EQ(a.surfaces.size(), b.surfaces.size());
  for (size_t i = 0; i < a.surfaces.size(); ++i) {
    const PrescriptionSurface& s = a.surfaces[i];
    const PrescriptionSurface& t = b.surfaces[i];
    EXPECT_EQ(s.shape.curvature_per_m, t.shape.curvature_per_m) << i;
    EXPECT_EQ(s.shape.conic, t.shape.conic) << i;
    EXPECT_EQ(s.shape.even_asphere, t.shape.even_asphere) << i;
    EXPECT_EQ(s.shape.fresnel_pitch_m, t.shape.fresnel_pitch_m) << i;
    EXPECT_EQ(s.shape.semi_diameter_m, t.shape.semi_diameter_m) << i;
    EXPECT_EQ(s.material, t.material) << i;
    EXPECT_EQ(s.thickness_m, t.thickness_m) << i;
  }
}

// Thorlabs LA1608 (thorlabs.com, N-BK7 plano-convex lenses): R 38.6 mm, tc 4.1
// mm, diameter 25.4 mm, f 75.0 mm and BFL 72.3 mm at 633 nm; curved side first.
TEST(LensZmx, La1608EveryNumber) {
  const Prescription p = ReadExampleLens("la1608.zmx");
  EXPECT_EQ(p.material_before, "air");
  EXPECT_EQ(p.stop_surface, -1);
  EXPECT_TRUE(p.placements.empty());
  ASSERT_EQ(p.surfaces.size(), 2u);
  EXPECT_TRUE(Close(1 / p.surfaces[0].shape.curvature_per_m, 38.6 * kMm, 1e-15));
  EXPECT_EQ(p.surfaces[0].material, "N-BK7");
  EXPECT_TRUE(Close(p.surfaces[0].thickness_m, 4.1 * kMm, 1e-15));
  EXPECT_EQ(p.surfaces[1].shape.curvature_per_m, 0.0);
  EXPECT_EQ(p.surfaces[1].material, "air");
  EXPECT_TRUE(Close(p.surfaces[1].thickness_m, 72.3 * kMm, 1e-15));  // the image plane at the BFL
  for (const PrescriptionSurface& s : p.surfaces) {
    EXPECT_EQ(s.shape.conic, 0.0);
    EXPECT_TRUE(s.shape.even_asphere.empty());
    EXPECT_EQ(s.shape.fresnel_pitch_m, 0.0);
    EXPECT_TRUE(Close(s.shape.semi_diameter_m, 12.7 * kMm, 1e-15));
  }
}

// Within the catalogue's rounding: R to 0.1 mm moves f by up to 0.1 mm, f and BFL are rounded to 0.1 mm.
TEST(LensZmx, La1608FocalLengthsAreThorlabs) {
  const ParaxialProperties p = ParaxialAt(LensSystem(ReadExampleLens("la1608.zmx")), kHeNe);
  EXPECT_NEAR(p.efl_m / kMm, 75.0, 0.15);
  EXPECT_NEAR(p.bfl_m / kMm, 72.3, 0.15);
}

// Two AC254-150-A (N-BK7 / SF5, R 91.6, -66.7, -197.7 mm, tc 5.7 and 2.2 mm),
// crown sides facing each other 2.0 mm apart, the image at 69.97 mm.
TEST(LensZmx, EyepieceEveryNumber) {
  const Prescription p = ReadExampleLens("plossl_ac254-150-a.zmx");
  const double radius_mm[] = {197.7, 66.7, -91.6, 91.6, -66.7, -197.7};
  const double thickness_mm[] = {2.2, 5.7, 2.0, 5.7, 2.2, 69.97};
  const char* material[] = {"SF5", "N-BK7", "air", "N-BK7", "SF5", "air"};
  EXPECT_EQ(p.material_before, "air");
  EXPECT_EQ(p.stop_surface, -1);
  ASSERT_EQ(p.surfaces.size(), 6u);
  for (size_t i = 0; i < 6; ++i) {
    const PrescriptionSurface& s = p.surfaces[i];
    EXPECT_TRUE(Close(1 / s.shape.curvature_per_m, radius_mm[i] * kMm, 1e-15)) << i;
    EXPECT_TRUE(Close(s.thickness_m, thickness_mm[i] * kMm, 1e-15)) << i;
    EXPECT_EQ(s.material, material[i]) << i;
    EXPECT_EQ(s.shape.conic, 0.0) << i;
    EXPECT_TRUE(s.shape.even_asphere.empty()) << i;
    EXPECT_TRUE(Close(s.shape.semi_diameter_m, 12.7 * kMm, 1e-15)) << i;
  }
}

// First-order optics by Gullstrand's combination, surface after surface: a
// system of power P with principal planes at z = h (front) and h2 (back),
// media n0 before and n1 after, followed by a surface of power Q = (n2 - n1) / R
// at z: e = z - h2, P' = P + Q - (e / n1) P Q, h' = h + n0 (e / n1) Q / P',
// h2' = z - n2 (e / n1) P / P'. Written apart from paraxial.cpp's matrices.
struct Gullstrand {
  double power = 0, front_z = 0, back_z = 0;
};

Gullstrand Combine(const std::vector<double>& radius_m, const std::vector<double>& thickness_m,
                   const std::vector<double>& index_after, double n_before) {
  Gullstrand g;
  double z = 0, n0 = n_before, n1 = n_before;
  for (size_t i = 0; i < radius_m.size(); ++i) {
    const double n2 = index_after[i];
    const double q = (n2 - n1) / radius_m[i];
    if (i == 0) {
      g = {q, z, z};
    } else {
      const double e = z - g.back_z;
      const double p = g.power + q - e / n1 * g.power * q;
      g = {p, g.front_z + n0 * (e / n1) * q / p, z - n2 * (e / n1) * g.power / p};
    }
    n1 = n2;
    z += thickness_m[i];
  }
  return g;
}

TEST(LensZmx, EyepieceFocalLengthsAgainstGullstrand) {
  const Prescription p = ReadExampleLens("plossl_ac254-150-a.zmx");
  const double n_bk7 = FindMaterial("N-BK7").Index(kD), n_sf5 = FindMaterial("SF5").Index(kD);
  const std::vector<double> radius = {197.7 * kMm, 66.7 * kMm, -91.6 * kMm, 91.6 * kMm, -66.7 * kMm, -197.7 * kMm};
  const std::vector<double> thickness = {2.2 * kMm, 5.7 * kMm, 2.0 * kMm, 5.7 * kMm, 2.2 * kMm, 0};
  const Gullstrand g = Combine(radius, thickness, {n_sf5, n_bk7, 1, n_bk7, n_sf5, 1}, 1.0);
  const double last_vertex = 17.8 * kMm;
  const double efl = 1 / g.power, bfl = g.back_z + efl - last_vertex;
  const ParaxialProperties paraxial = ParaxialAt(LensSystem(p), kD);
  EXPECT_TRUE(Close(paraxial.efl_m, efl, 1e-12));
  EXPECT_TRUE(Close(paraxial.bfl_m, bfl, 0, 1e-12 * efl));
  EXPECT_NEAR(efl / kMm, 76.1, 0.05);  // "about 75 mm"
  // The file's image plane is the paraxial back focus rounded to 0.01 mm.
  EXPECT_NEAR(p.surfaces.back().thickness_m / kMm, bfl / kMm, 0.005);

  // Each achromat alone (the second one, as read) against Thorlabs' f = 150.0 mm, BFL 146.1 mm at
  // 587.6 nm, within the rounding of its radii to 0.1 mm (0.1 mm of f).
  Prescription doublet;
  doublet.surfaces.assign(p.surfaces.begin() + 3, p.surfaces.end());
  const ParaxialProperties one = ParaxialAt(LensSystem(doublet), kD);
  EXPECT_NEAR(one.efl_m / kMm, 150.0, 0.1);
  EXPECT_NEAR(one.bfl_m / kMm, 146.1, 0.1);
}

TEST(LensZmx, ShippedFilesRoundTrip) {
  for (const char* name : {"la1608.zmx", "plossl_ac254-150-a.zmx"}) {
    SCOPED_TRACE(name);
    const Prescription read = ReadExampleLens(name);
    const std::string written = WriteZmx(read, name);
    const Prescription again = ReadZmx(written, "written.zmx");
    ExpectSame(again, read);
    EXPECT_EQ(WriteZmx(again, name), written);  // stable: the text is a fixed point
  }
  // In millimeters, with the fewest digits that read back exactly.
  const std::string la1608 = WriteZmx(ReadExampleLens("la1608.zmx"), "LA1608");
  EXPECT_NE(la1608.find("\r\n  DISZ 4.1\r\n  GLAS N-BK7 0 0 "), std::string::npos) << la1608;
  EXPECT_NE(la1608.find("\r\n  DISZ 72.3\r\n  DIAM 12.7 1 0 0 1 \"\"\r\nSURF 3\r\n"), std::string::npos) << la1608;
}

// A lens written here, line by line, for the refusals (line numbers matter).
const std::vector<std::string> kLens = {
    "MODE SEQ",         // 1
    "UNIT MM",          // 2
    "SURF 0",           // 3
    "  DISZ INFINITY",  // 4
    "SURF 1",           // 5
    "  TYPE STANDARD",  // 6
    "  CURV 0.02",      // 7
    "  DISZ 5",         // 8
    "  GLAS N-BK7",     // 9
    "  DIAM 10",        // 10
    "SURF 2",           // 11
    "  CURV -0.02",     // 12
    "  DISZ 40",        // 13
    "  DIAM 10",        // 14
    "SURF 3",           // 15
    "  CURV 0",         // 16
};

std::string Join(const std::vector<std::string>& lines) {
  std::string text;
  for (const std::string& l : lines) text += l + "\n";
  return text;
}

// kLens edited by `edit`.
template <class Edit>
std::string Edited(Edit&& edit) {
  std::vector<std::string> lines = kLens;
  edit(lines);
  return Join(lines);
}

// kLens with line `number` (1-based) replaced by `text`.
std::string Replaced(int number, const std::string& text) {
  std::vector<std::string> lines = kLens;
  lines[number - 1] = text;
  return Join(lines);
}

// kLens with `text` inserted after line `after`.
std::string Inserted(int after, const std::string& text) {
  std::vector<std::string> lines = kLens;
  lines.insert(lines.begin() + after, text);
  return Join(lines);
}

std::string ReadError(const std::string& text) {
  return ErrorOf([&] { ReadZmx(text, "t.zmx"); });
}

TEST(LensZmx, TheHandWrittenLensReads) {
  const Prescription p = ReadZmx(Join(kLens), "t.zmx");
  ASSERT_EQ(p.surfaces.size(), 2u);
  EXPECT_TRUE(Close(p.surfaces[0].shape.curvature_per_m, 20.0, 1e-15));
  EXPECT_TRUE(Close(p.surfaces[1].shape.curvature_per_m, -20.0, 1e-15));
  EXPECT_TRUE(Close(p.surfaces[0].thickness_m, 5e-3, 1e-15));
  EXPECT_TRUE(Close(p.surfaces[1].thickness_m, 40e-3, 1e-15));
  // The object distance is the conjugate, not the lens: a finite one reads the same.
  ExpectSame(ReadZmx(Replaced(4, "  DISZ 250"), "t.zmx"), p);
}

TEST(LensZmx, RefusalsNameTheLine) {
  EXPECT_EQ(ReadError(Replaced(6, "  TYPE TOROIDAL")),
            "t.zmx:6: surface type TOROIDAL is not supported (STANDARD and EVENASPH only)");
  EXPECT_EQ(ReadError(Replaced(6, "  TYPE COORDBRK")),
            "t.zmx:6: surface type COORDBRK is not supported (STANDARD and EVENASPH only)");
  EXPECT_EQ(ReadError(Inserted(7, "  PARM 2 1e-6")),
            "t.zmx:8: PARM 2 on a STANDARD surface (TYPE EVENASPH for an asphere)");
  EXPECT_EQ(ReadError(Edited([](std::vector<std::string>& l) {
              l[5] = "  TYPE EVENASPH";
              l.insert(l.begin() + 7, "  PARM 1 0.001");
            })),
            "t.zmx:8: PARM 1, the r^2 term, is not supported (the even asphere starts at r^4; with CURV it is no "
            "conic)");
  EXPECT_EQ(ReadError(Replaced(9, "  GLAS MIRROR")), "t.zmx:9: mirrors are not supported (refracting surfaces only)");
  EXPECT_EQ(ReadError(Replaced(9, "  GLAS ___BLANK 1 0 1.5 60")),
            "t.zmx:9: model glass (___BLANK) is not supported: name a catalogue glass");
  EXPECT_EQ(ReadError(Replaced(9, "  GLAS BK7 0 0")),
            "t.zmx:9: unknown glass \"BK7\" (the catalogue knows air, N-BK7, N-SF11, N-F2, N-LAK22, N-SF5, N-BAF10, "
            "SF5, PMMA, PC, E48R)");
  EXPECT_EQ(ReadError(Inserted(12, "  TILT 0 0.5 0")),
            "t.zmx:13: \"  TILT 0 0.5 0\": TILT is not in the supported .zmx subset (docs/optics.md, \"Real lenses\")");
  EXPECT_EQ(ReadError(Inserted(12, "  XDAT 1 0.5")),
            "t.zmx:13: \"  XDAT 1 0.5\": XDAT is not in the supported .zmx subset (docs/optics.md, \"Real lenses\")");
  EXPECT_EQ(ReadError(Replaced(13, "  DISZ INFINITY")), "t.zmx:13: DISZ INFINITY is only for the object surface");
  EXPECT_EQ(ReadError(Replaced(1, "MODE NSC")), "t.zmx:1: only sequential files (MODE SEQ) are supported");
  EXPECT_EQ(ReadError(Inserted(16, "MNUM 2 1")), "t.zmx:17: multi-configuration files (MNUM > 1) are not supported");
  EXPECT_EQ(ReadError(Replaced(2, "UNIT FT")), "t.zmx:2: lens units must be MM, CM, IN or METER");
  EXPECT_EQ(ReadError(Edited([](std::vector<std::string>& l) {
              l.insert(l.begin() + 5, "  STOP");   // line 6, in SURF 1
              l.insert(l.begin() + 12, "  STOP");  // line 13, in SURF 2
            })),
            "t.zmx:13: a second STOP (the first is at line 6)");
  EXPECT_EQ(ReadError(Replaced(16, "  CURV 0.01")), "t.zmx:16: the image surface must be a plane (CURV 0)");
  EXPECT_EQ(ReadError(Inserted(3, "  STOP")), "t.zmx:4: the stop cannot be the object surface");
  EXPECT_EQ(ReadError(Inserted(14, "  CLAP 2 8 0")),
            "t.zmx:15: an annular aperture (CLAP with a minimum radius) is not supported");
  EXPECT_EQ(ReadError(Replaced(10, "  DIAM -1")), "t.zmx:10: expected a semi-diameter >= 0 (0: no aperture)");
  EXPECT_EQ(ReadError(Replaced(7, "  CURV 0.02x")), "t.zmx:7: \"0.02x\" is not a finite number");
  EXPECT_EQ(ReadError(Replaced(7, "  CURV nan")), "t.zmx:7: \"nan\" is not a finite number");
  EXPECT_EQ(ReadError(Replaced(7, "  CURV 1e999")), "t.zmx:7: \"1e999\" is not a finite number");
  EXPECT_EQ(ReadError(Replaced(11, "SURF 3")), "t.zmx:11: expected SURF 2 (surfaces numbered 0, 1, ... in order)");
  EXPECT_EQ(ReadError(Inserted(7, "  CURV 0.03")), "t.zmx:8: CURV given twice in SURF 1 (first at line 7)");
  EXPECT_EQ(ReadError(Replaced(3, "  CURV 0")), "t.zmx:3: CURV outside a SURF block");
  EXPECT_EQ(ReadError("MODE SEQ\nSURF 0\nSURF 1\n"),
            "t.zmx: 2 SURF blocks; a lens needs the object (SURF 0), at least one surface and the image");
  // What LensSystem refuses, moved to the surface's SURF line: a sphere of
  // radius 5 mm cannot have a 10 mm semi-diameter.
  EXPECT_EQ(ReadError(Replaced(7, "  CURV 0.2")),
            "t.zmx:5: SURF 1: the clear aperture reaches beyond the conic's edge, where its sag is undefined "
            "(/surfaces/0/semi_diameter_m)");
}

// EVENASPH: PARM n is the coefficient of r^(2n) in lens units^(1 - 2n), our
// even_asphere[n - 2]; the sag checked against the formula in millimeters.
TEST(LensZmx, EvenAsphereConicStopAndMaterialBefore) {
  std::vector<std::string> lines = kLens;
  lines[5] = "  TYPE EVENASPH";
  lines.insert(lines.begin() + 7, {"  CONI -1.5", "  PARM 1 0", "  PARM 2 3.5E-5", "  PARM 3 -1.25E-8", "  PARM 4 0",
                                   "  PARM 5 2E-13", "  STOP"});
  lines.insert(lines.begin() + 3, "  GLAS PMMA");
  const Prescription p = ReadZmx(Join(lines), "asphere.zmx");
  EXPECT_EQ(p.material_before, "PMMA");
  EXPECT_EQ(p.stop_surface, 0);
  const SurfaceShape& s = p.surfaces[0].shape;
  EXPECT_EQ(s.conic, -1.5);
  ASSERT_EQ(s.even_asphere.size(), 4u);  // r^4, r^6, r^8, r^10
  EXPECT_TRUE(Close(s.even_asphere[0], 3.5e-5 * 1e9, 1e-15));
  EXPECT_TRUE(Close(s.even_asphere[1], -1.25e-8 * 1e15, 1e-15));
  EXPECT_EQ(s.even_asphere[2], 0.0);
  EXPECT_TRUE(Close(s.even_asphere[3], 2e-13 * 1e27, 1e-15));
  for (double r_mm : {2.0, 5.0, 9.0}) {
    const double c = 0.02, k = -1.5;
    const double sag_mm = c * r_mm * r_mm / (1 + std::sqrt(1 - (1 + k) * c * c * r_mm * r_mm)) +
                          3.5e-5 * std::pow(r_mm, 4) - 1.25e-8 * std::pow(r_mm, 6) + 2e-13 * std::pow(r_mm, 10);
    EXPECT_TRUE(Close(Surface(s).Sag(r_mm * kMm), sag_mm * kMm, 1e-13)) << r_mm;
  }
  const std::string written = WriteZmx(p, "asphere");
  ExpectSame(ReadZmx(written, "written.zmx"), p);
  EXPECT_NE(written.find("  TYPE EVENASPH\r\n  CURV 0.02\r\n  CONI -1.5\r\n  PARM 1 0\r\n  PARM 2 3.5E-05\r\n"
                         "  PARM 3 -1.25E-08\r\n  PARM 4 0\r\n  PARM 5 2E-13\r\n"),
            std::string::npos)
      << written;
}

// The same lens in every lens unit: 1 in = 25.4 mm exactly.
TEST(LensZmx, LensUnitsGiveTheSameMeters) {
  auto lens = [](const std::string& unit, double per_mm) {
    // CURV scales as 1/length, PARM 2 (r^4) as 1/length^3.
    std::vector<std::string> lines = {"UNIT " + unit, "SURF 0", "SURF 1", "TYPE EVENASPH"};
    auto number = [](double v) {
      std::ostringstream s;
      s.precision(17);
      s << v;
      return s.str();
    };
    lines.push_back("CURV " + number(0.02 / per_mm));
    lines.push_back("PARM 2 " + number(1e-6 / (per_mm * per_mm * per_mm)));
    lines.push_back("DISZ " + number(5.08 * per_mm));
    lines.push_back("GLAS N-BK7");
    lines.push_back("DIAM " + number(12.7 * per_mm));
    lines.push_back("SURF 2");
    lines.push_back("DISZ " + number(50.8 * per_mm));
    lines.push_back("SURF 3");
    return ReadZmx(Join(lines), unit + ".zmx");
  };
  for (const auto& [unit, per_mm] :
       std::vector<std::pair<std::string, double>>{{"MM", 1.0}, {"CM", 0.1}, {"IN", 1 / 25.4}, {"METER", 1e-3}}) {
    SCOPED_TRACE(unit);
    const Prescription p = lens(unit, per_mm);
    EXPECT_TRUE(Close(p.surfaces[0].shape.curvature_per_m, 20.0, 1e-14));
    EXPECT_TRUE(Close(p.surfaces[0].shape.even_asphere.at(0), 1e-6 * 1e9, 1e-14));
    EXPECT_TRUE(Close(p.surfaces[0].thickness_m, 5.08e-3, 1e-14));
    EXPECT_TRUE(Close(p.surfaces[0].shape.semi_diameter_m, 12.7e-3, 1e-14));
    EXPECT_TRUE(Close(p.surfaces[1].thickness_m, 50.8e-3, 1e-14));
    const std::string written = WriteZmx(p, unit);
    ExpectSame(ReadZmx(written, "written.zmx"), p);
    EXPECT_EQ(WriteZmx(ReadZmx(written, "written.zmx"), unit), written);
  }
  // Short decimals in inches, by hand: 0.2 in = 5.08 mm, 0.5 in = 12.7 mm, CURV 0.5 /in = 1 / 50.8 mm.
  const Prescription in =
      ReadZmx("UNIT IN\nSURF 0\nSURF 1\nCURV 0.5\nDISZ 0.2\nDIAM 0.5\nGLAS N-BK7\nSURF 2\nSURF 3\n", "inches.zmx");
  EXPECT_TRUE(Close(in.surfaces[0].thickness_m, 5.08e-3, 1e-15));
  EXPECT_TRUE(Close(in.surfaces[0].shape.semi_diameter_m, 12.7e-3, 1e-15));
  EXPECT_TRUE(Close(in.surfaces[0].shape.curvature_per_m, 1 / 50.8e-3, 1e-15));
}

// zmx_fuzz's first finding: an r^4 term of 1E-3 in^-3 has no millimeter
// double that converts back to it (0.0254^3 spreads the doubles apart), so
// the writer falls back to meters, where every double has its digits.
TEST(LensZmx, AsphereInInchesRoundTripsThroughMeters) {
  const Prescription p = ReadZmx(ReadBytes(std::string(LAYERLAB_SOURCE_DIR) + "/fuzz/corpus/zmx/asphere_inches.zmx"),
                                 "asphere_inches.zmx");
  EXPECT_TRUE(Close(p.surfaces[0].shape.even_asphere.at(0), 1e-3 / (0.0254 * 0.0254 * 0.0254), 1e-15));
  const std::string written = WriteZmx(p, "inches");
  EXPECT_NE(written.find("\r\nUNIT METER "), std::string::npos) << written;
  ExpectSame(ReadZmx(written, "written.zmx"), p);
  EXPECT_EQ(WriteZmx(ReadZmx(written, "written.zmx"), "inches"), written);
  // The shipped files, read from millimeters, stay in millimeters.
  EXPECT_NE(WriteZmx(ReadExampleLens("la1608.zmx"), "").find("\r\nUNIT MM "), std::string::npos);
}

std::string Utf16Le(const std::u16string& text) {
  std::string bytes = "\xFF\xFE";
  for (char16_t c : text) {
    bytes += static_cast<char>(c & 0xFF);
    bytes += static_cast<char>(c >> 8);
  }
  return bytes;
}

std::u16string Widen(const std::string& ascii) { return std::u16string(ascii.begin(), ascii.end()); }

// OpticStudio saves UTF-16LE with a BOM; Thorlabs' files carry "Ø" in NAME.
TEST(LensZmx, Utf16LeAndUtf8) {
  const std::string utf8 = ReadBytes(ExamplePath("lenses/la1608.zmx"));
  const Prescription expected = ReadZmx(utf8, "la1608.zmx");
  // U+00D8 and a character outside the BMP (a surrogate pair), both in ignored lines.
  const std::u16string wide = u"NAME \u00D8 25.4 mm\r\nNOTE 0 \U0001F50D\r\n" + Widen(utf8);
  ExpectSame(ReadZmx(Utf16Le(wide), "wide.zmx"), expected);
  ExpectSame(ReadZmx("\xEF\xBB\xBF" + utf8, "bom.zmx"), expected);
  ExpectSame(ReadZmx("NAME \xD8 Latin-1\n" + utf8, "latin1.zmx"), expected);  // ignored text, any bytes
}

TEST(LensZmx, OtherEncodingsAreRefused) {
  const std::string utf8 = ReadBytes(ExamplePath("lenses/la1608.zmx"));
  std::string be = "\xFE\xFF";
  for (char c : utf8) be += std::string(1, '\0') + c;
  EXPECT_EQ(ErrorOf([&] { ReadZmx(be, "be.zmx"); }),
            "be.zmx: UTF-16BE text is not supported (save the .zmx as UTF-8 or UTF-16LE)");
  const std::string no_bom = Utf16Le(Widen(utf8)).substr(2);
  EXPECT_EQ(ErrorOf([&] { ReadZmx(no_bom, "nobom.zmx"); }),
            "nobom.zmx:1: a NUL byte (UTF-16 without its byte-order mark? .zmx files are read as UTF-8, or as "
            "UTF-16LE with its BOM)");
  EXPECT_EQ(ErrorOf([&] { ReadZmx(std::string("\xFF\xFE\0\0", 4) + "x", "u32.zmx"); }),
            "u32.zmx: UTF-32 text is not supported (save the .zmx as UTF-8 or UTF-16LE)");
  EXPECT_EQ(ErrorOf([&] { ReadZmx(Utf16Le(u"SURF 0") + "x", "odd.zmx"); }),
            "odd.zmx: UTF-16LE text of an odd number of bytes (15)");
  std::u16string unpaired = u"NAME\nNOTE ";
  unpaired += static_cast<char16_t>(0xD800);
  unpaired += u" x";
  EXPECT_EQ(ErrorOf([&] { ReadZmx(Utf16Le(unpaired), "surrogate.zmx"); }),
            "surrogate.zmx:2: invalid UTF-16LE (an unpaired surrogate)");
}

TEST(LensZmx, WriterRefusesWhatTheSubsetCannotHold) {
  Prescription p = ReadZmx(Join(kLens), "t.zmx");
  Prescription fresnel = p;
  fresnel.surfaces[0].shape.fresnel_pitch_m = 0.5e-3;
  EXPECT_EQ(ErrorOf([&] { WriteZmx(fresnel, ""); }),
            "WriteZmx: surface 0: a Fresnel surface has no STANDARD or EVENASPH form");
  Prescription tilted = p;
  tilted.placements = {{0, 1, 0.01, 0, 0, 0}};
  EXPECT_EQ(ErrorOf([&] { WriteZmx(tilted, ""); }),
            "WriteZmx: placements (tilts, decentres) cannot be written: the .zmx subset has no coordinate breaks");
  Prescription long_asphere = p;
  long_asphere.surfaces[1].shape.even_asphere.assign(8, 0.0);
  EXPECT_EQ(ErrorOf([&] { WriteZmx(long_asphere, ""); }),
            "WriteZmx: surface 1: 8 aspheric terms; EVENASPH holds r^4 to r^16 (7)");
}

}  // namespace
}  // namespace layerlab::lenses
