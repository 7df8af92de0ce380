// Combiner efficiencies against Malus's law and hand-worked Jones products.
#include <cmath>
#include <numbers>

#include "layerlab/framework/polarization.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

using testing::Close;
using testing::CompileJson;
using testing::ElementNamed;
using testing::ReadExample;

constexpr double kPi = std::numbers::pi;

TEST(Polarization, HalfWavePlateAt45DegreesSwapsXAndY) {
  Jones out = Retarder(kPi, kPi / 4) * LinearPolarization(0);
  EXPECT_TRUE(Close(std::norm(out.x), 0, 0, 1e-15));
  EXPECT_TRUE(Close(std::norm(out.y), 1, 1e-15));
  // A retarder of retardance delta at 45 deg moves sin^2(delta / 2) of x light into y.
  for (double delta : {0.3, 1.0, 2.5}) {
    Jones r = Retarder(delta, kPi / 4) * LinearPolarization(0);
    EXPECT_TRUE(Close(std::norm(r.y), std::pow(std::sin(delta / 2), 2), 1e-12));
    EXPECT_TRUE(Close(r.intensity(), 1, 1e-12));  // lossless
  }
}

// The PBS/HWP example with flat (per-channel) efficiencies so the hand
// calculation needs no interpolation.
nlohmann::json FlatPbsScene(double panel_angle_deg) {
  nlohmann::json scene = ReadExample("hybrid_pbs_hwp.json");
  nlohmann::json& pbs = ElementNamed(scene, "pbs");
  pbs["transmittance_p"] = {0.9, 0.95, 0.8};
  pbs["reflectance_s"] = {0.99, 0.98, 0.97};
  pbs["transmittance_s"] = 0.01;
  pbs["reflectance_p"] = 0.02;
  ElementNamed(scene, "front_a")["polarization"] = std::to_string(panel_angle_deg) + " deg";
  ElementNamed(scene, "front_b")["polarization"] = std::to_string(panel_angle_deg) + " deg";
  return scene;
}

// By hand: R(t) diag(1, -1) R(-t) = [[cos 2t, sin 2t], [sin 2t, -cos 2t]] takes (cos p, sin p) to
// (cos(2t - p), sin(2t - p)): linear light mirrored about the fast axis, nothing lost. At 45 deg and p = 0
// a wrong axis sign or a swapped sine and cosine give the same intensities; at the other angles they do not.
TEST(Polarization, HalfWavePlateAtAnyAngleMirrorsLinearPolarizationAboutItsFastAxis) {
  for (double axis_deg : {0.0, 22.5, 30.0, 45.0, 67.5, 100.0})
    for (double in_deg : {0.0, 30.0, 90.0}) {
      const double axis = axis_deg * kPi / 180, in = in_deg * kPi / 180, out = 2 * axis - in;
      const Jones j = Retarder(kPi, axis) * LinearPolarization(in);
      EXPECT_NEAR(j.x.real(), std::cos(out), 1e-15) << axis_deg << " deg, light at " << in_deg << " deg";
      EXPECT_NEAR(j.y.real(), std::sin(out), 1e-15) << axis_deg << " deg, light at " << in_deg << " deg";
      EXPECT_NEAR(j.x.imag(), 0, 1e-15);
      EXPECT_NEAR(j.y.imag(), 0, 1e-15);
      EXPECT_NEAR(j.intensity(), 1, 1e-15);
    }
}

// The compiled reflected branch of the PBS/HWP hybrid at other plate angles and panel polarizations: the
// plate turns the panel's light at p to 2t - p, and the PBS (p axis 0 deg) reflects its y part.
TEST(Polarization, ReflectedBranchFollowsTheHalfWavePlatesAngle) {
  const double rs[] = {0.99, 0.98, 0.97}, rp = 0.02, hwp_t = 0.99;
  for (double axis_deg : {0.0, 22.5, 30.0, 45.0, 60.0})
    for (double panel_deg : {0.0, 30.0}) {
      nlohmann::json scene = FlatPbsScene(panel_deg);
      nlohmann::json& hwp = ElementNamed(scene, "hwp");
      hwp["fast_axis"] = std::to_string(axis_deg) + " deg";
      hwp["achromatic"] = true;
      hwp["transmittance"] = hwp_t;
      const DisplaySystem s = CompileJson(scene);
      const double out = (2 * axis_deg - panel_deg) * kPi / 180;
      for (int c = 0; c < 3; ++c) {
        const double expected = hwp_t * (rs[c] * std::pow(std::sin(out), 2) + rp * std::pow(std::cos(out), 2));
        EXPECT_TRUE(Close(s.branches[1].optics_efficiency[c], expected, 1e-12))
            << "plate at " << axis_deg << " deg, panel at " << panel_deg << " deg, channel " << c << ": "
            << s.branches[1].optics_efficiency[c] << " against " << expected;
      }
    }
}

TEST(Polarization, PbsTransmittedBranchFollowsMalus) {
  const double tp[] = {0.9, 0.95, 0.8}, ts = 0.01;
  for (double angle : {0.0, 30.0, 90.0}) {
    DisplaySystem s = CompileJson(FlatPbsScene(angle));
    double a = angle * kPi / 180;
    for (int c = 0; c < 3; ++c) {
      double expected = tp[c] * std::pow(std::cos(a), 2) + ts * std::pow(std::sin(a), 2);
      EXPECT_TRUE(Close(s.branches[0].optics_efficiency[c], expected, 1e-12)) << angle << " deg, channel " << c;
    }
  }
}

TEST(Polarization, ReflectedBranchThroughAZeroOrderHalfWavePlate) {
  DisplaySystem s = CompileJson(FlatPbsScene(0));
  const double rs[] = {0.99, 0.98, 0.97}, rp = 0.02, hwp_t = 0.99;
  const double wavelength[] = {612e-9, 549e-9, 465e-9};
  for (int c = 0; c < 3; ++c) {
    double delta = kPi * 550e-9 / wavelength[c];  // zero-order plate designed at 550 nm
    double to_s = std::pow(std::sin(delta / 2), 2);
    double expected = hwp_t * (rs[c] * to_s + rp * (1 - to_s));
    EXPECT_TRUE(Close(s.branches[1].optics_efficiency[c], expected, 1e-12)) << "channel " << c;
  }
  // Off its design wavelength the plate leaks: red and blue lose more than green.
  EXPECT_LT(s.branches[1].optics_efficiency[0], s.branches[1].optics_efficiency[1] * rs[0] / rs[1]);
}

// A multi-order plate of order m has retardance (2m + 1) pi lambda0 / lambda: a half wave at its design wavelength
// at every order, and more chromatic the higher the order. Order 0 cannot tell (2m + 1) from m + 1.
TEST(Polarization, ReflectedBranchThroughAMultiOrderHalfWavePlate) {
  const double rs[] = {0.99, 0.98, 0.97}, rp = 0.02, hwp_t = 0.99;
  const double wavelength[] = {612e-9, 549e-9, 465e-9};
  for (int order : {1, 2, 5})
    for (double design_nm : {549.0, 600.0}) {
      nlohmann::json scene = FlatPbsScene(0);
      nlohmann::json& hwp = ElementNamed(scene, "hwp");
      hwp["order"] = order;
      hwp["design_wavelength"] = std::to_string(design_nm) + " nm";
      const DisplaySystem s = CompileJson(scene);
      for (int c = 0; c < 3; ++c) {
        const double delta = (2 * order + 1) * kPi * design_nm * 1e-9 / wavelength[c];
        const double to_s = std::pow(std::sin(delta / 2), 2);
        const double expected = hwp_t * (rs[c] * to_s + rp * (1 - to_s));
        EXPECT_TRUE(Close(s.branches[1].optics_efficiency[c], expected, 1e-12))
            << "order " << order << " at " << design_nm << " nm, channel " << c << ": "
            << s.branches[1].optics_efficiency[c] << " against " << expected;
      }
    }
}

TEST(Polarization, SpectralTablesAreInterpolatedAtTheChannels) {
  nlohmann::json scene = FlatPbsScene(0);
  ElementNamed(scene, "pbs")["transmittance_p"] = {{"wavelengths", {"400 nm", "500 nm", "700 nm"}},
                                                   {"values", {0.5, 0.7, 0.9}}};
  DisplaySystem s = CompileJson(scene);
  EXPECT_TRUE(Close(s.branches[0].optics_efficiency[0], 0.7 + 0.2 * (612 - 500) / 200.0, 1e-12));
  EXPECT_TRUE(Close(s.branches[0].optics_efficiency[1], 0.7 + 0.2 * (549 - 500) / 200.0, 1e-12));
  EXPECT_TRUE(Close(s.branches[0].optics_efficiency[2], 0.5 + 0.2 * (465 - 400) / 100.0, 1e-12));
}

TEST(Polarization, IdealPbsAndHwpLoseNothing) {
  nlohmann::json scene = ReadExample("hybrid_pbs_hwp.json");
  nlohmann::json& pbs = ElementNamed(scene, "pbs");
  for (const char* key : {"transmittance_p", "reflectance_s"}) pbs[key] = 1;
  for (const char* key : {"transmittance_s", "reflectance_p"}) pbs[key] = 0;
  nlohmann::json& hwp = ElementNamed(scene, "hwp");
  hwp["achromatic"] = true;
  hwp["transmittance"] = 1;
  DisplaySystem s = CompileJson(scene);
  // The paper's conclusion: with a PBS and HWP the combiner costs nothing,
  // so the hybrid is as bright as a 2-layer multiplicative display.
  EXPECT_TRUE(Close(s.luminance_efficiency, 0.09, 1e-12));
}

}  // namespace
}  // namespace layerlab

namespace layerlab {
namespace {

// An eye, in-line `optics` (nearest the eye first), a lens and one panel whose exit polarizer is along x.
nlohmann::json InlineOptics(const std::vector<nlohmann::json>& optics) {
  nlohmann::json s = {{"format", "layerlab-scene/1"}, {"name", "in-line polarization"}};
  nlohmann::json e = nlohmann::json::array();
  e.push_back({{"type", "eye"}, {"name", "eye"}, {"pupil_samples", {3, 3}}, {"views", {3, 3}}});
  for (size_t k = 0; k < optics.size(); ++k) {
    nlohmann::json o = optics[k];
    o["name"] = "optic" + std::to_string(k);
    e.back()["next"] = o["name"];
    e.push_back(o);
  }
  e.back()["next"] = "lens";
  e.push_back({{"type", "thin_lens"}, {"name", "lens"}, {"focal_length", "50 mm"}, {"next", "panel"}});
  e.push_back({{"type", "lc_panel"},
               {"name", "panel"},
               {"virtual_depth", "1 D"},
               {"pixel_pitch", "100 um"},
               {"resolution", {20, 10}},
               {"max_transmittance", 1.0},
               {"next", "light"}});
  e.push_back({{"type", "backlight"}, {"name", "light"}, {"luminance", "100 cd/m2"}});
  s["elements"] = e;
  return s;
}

double Efficiency(const std::vector<nlohmann::json>& optics) {
  return CompileJson(InlineOptics(optics)).branches[0].optics_efficiency[1];
}

// By hand: the panel's light is x-polarized. A quarter-wave plate at 45 deg makes it circular, which a linear
// polarizer at any angle passes at half; two of them are a half-wave plate, turning x into y; a polarizer passes
// cos^2 of its angle to linear light (Malus).
TEST(Polarization, QuarterWavePlatesAndALinearPolarizerByJonesCalculus) {
  const nlohmann::json qwp = {{"type", "qwp"}, {"fast_axis", "45 deg"}, {"achromatic", true}};
  auto polarizer = [](double deg) {
    return nlohmann::json{{"type", "linear_polarizer"}, {"axis", std::to_string(deg) + " deg"}};
  };
  for (double deg : {0.0, 30.0, 90.0, 135.0}) {
    const double a = deg * kPi / 180;
    SCOPED_TRACE(std::to_string(deg) + " deg");
    EXPECT_NEAR(Efficiency({polarizer(deg)}), std::pow(std::cos(a), 2), 1e-12);            // Malus
    EXPECT_NEAR(Efficiency({polarizer(deg), qwp}), 0.5, 1e-12);                            // circular
    EXPECT_NEAR(Efficiency({polarizer(deg), qwp, qwp}), std::pow(std::sin(a), 2), 1e-12);  // x turned to y
  }
  // A zero-order quarter-wave plate is a quarter wave at its design wavelength only (green, 549 nm, here): a
  // retarder of delta at 45 deg leaves x-polarized light |E_x|^2 = cos^2(delta / 2) along x, delta = (pi / 2)
  // 549 nm / lambda.
  const nlohmann::json green_qwp = {{"type", "qwp"}, {"fast_axis", "45 deg"}, {"design_wavelength", "549 nm"}};
  const DisplaySystem s = CompileJson(InlineOptics({polarizer(0), green_qwp}));
  const double wavelength[] = {612e-9, 549e-9, 465e-9};
  for (int c = 0; c < 3; ++c) {
    const double delta = kPi / 2 * 549e-9 / wavelength[c];
    EXPECT_NEAR(s.branches[0].optics_efficiency[c], std::pow(std::cos(delta / 2), 2), 1e-12) << "channel " << c;
  }
  // Along the panel's own polarization a polarizer passes its transmittance (natural light: tests/see_through_test.cpp).
  EXPECT_NEAR(Efficiency({{{"type", "linear_polarizer"}, {"transmittance", 0.8}}}), 0.8, 1e-12);
}

}  // namespace
}  // namespace layerlab
