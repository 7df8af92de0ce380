// `layerlab tolerance` (analysis/tolerance*.h): the draws (a truncated
// normal's moments from its closed form, seeding), perturbations whose
// misregistration is known by hand (a decentred panel, a moved panel behind
// an ideal magnifier), the sensitivity ranking where the answer is known,
// and hostile tolerance values refused by pointer.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "layerlab/analysis/tolerance.h"
#include "layerlab/analysis/tolerance_report.h"
#include "layerlab/framework/json_file.h"
#include "layerlab/systems/compile.h"

namespace layerlab {
namespace {

const std::string kIdeal = std::string(LAYERLAB_SOURCE_DIR) + "/examples/paper_prototype.json";
constexpr double kPitch = 117e-6, kFocal = 75e-3, kEyeRelief = 10e-3;

ToleranceSpec Spec(const nlohmann::json& object) { return ReadToleranceSpec(object, Location{"tol.json", ""}); }

struct Ideal {
  Scene scene = LoadScene(kIdeal);
  DisplaySystem designed = Compile(scene);
};

const Ideal& IdealPrototype() {
  static const Ideal ideal;
  return ideal;
}

size_t DofIndex(const ToleranceModel& model, const std::string& name) {
  for (size_t i = 0; i < model.dofs().size(); ++i)
    if (model.dofs()[i].Name() == name) return i;
  throw Error("no degree of freedom " + name);
}

const LayerResult& LayerOf(const ToleranceResult& r, const std::string& name) {
  for (const LayerResult& l : r.layers)
    if (l.layer == name) return l;
  throw Error("no layer " + name);
}

const VirtualLayer& Named(const DisplaySystem& s, const std::string& name) {
  for (const VirtualLayer& l : s.layers)
    if (l.name == name) return l;
  throw Error("no layer " + name);
}

// Normal of sigma = L / 2 truncated at +-L, i.e. the standard normal at +-2:
// variance 1 - 2 a phi(a) / (2 Phi(a) - 1) at a = 2, and the share beyond 1 sigma.
TEST(ToleranceDraws, TruncatedNormalHasTheClosedFormsMoments) {
  const double a = 2, phi = std::exp(-a * a / 2) / std::sqrt(2 * std::numbers::pi);
  auto Phi = [](double x) { return 0.5 * (1 + std::erf(x / std::sqrt(2.0))); };
  const double inside = 2 * Phi(a) - 1;
  const double sd = std::sqrt(1 - 2 * a * phi / inside) / 2;  // in units of the limit
  const double beyond_sigma = 2 * (Phi(2) - Phi(1)) / inside;
  Gaussian random(42);
  const int n = 200000;
  double sum = 0, square = 0, largest = 0;
  int beyond = 0;
  for (int i = 0; i < n; ++i) {
    const double x = DrawTruncatedNormal(random, 3.0) / 3.0;
    sum += x, square += x * x, largest = std::max(largest, std::abs(x));
    beyond += std::abs(x) > 0.5;
  }
  EXPECT_LE(largest, 1.0) << "truncated at the limit";
  EXPECT_GT(largest, 0.95) << "but reaching it";
  EXPECT_NEAR(sum / n, 0.0, 0.005);
  EXPECT_NEAR(std::sqrt(square / n), sd, 0.01 * sd);
  EXPECT_NEAR(double(beyond) / n, beyond_sigma, 0.005);
  Gaussian zero(1);
  EXPECT_EQ(DrawTruncatedNormal(zero, 0.0), 0.0);
}

TEST(ToleranceDraws, TheSameSeedAndSampleGiveTheSameDraw) {
  const Ideal& ideal = IdealPrototype();
  const ToleranceModel model(ideal.scene, ideal.designed, Spec({{"panel_decentre", "0.05 mm"}, {"gap", "0.1 mm"}}));
  ASSERT_EQ(model.dofs().size(), 12u) << "4 panels x 2 axes, 4 gaps";
  EXPECT_EQ(model.Draw(7, 3), model.Draw(7, 3));
  EXPECT_NE(model.Draw(7, 3), model.Draw(8, 3));
  EXPECT_NE(model.Draw(7, 3), model.Draw(7, 4));
  for (size_t i = 0; i < model.dofs().size(); ++i) EXPECT_LE(std::abs(model.Draw(7, 3)[i]), model.dofs()[i].limit);
}

// Placed physically, the nominal display is the designed one.
TEST(ToleranceModelTest, ThePhysicalPlacementsCompileToTheDesign) {
  const Ideal& ideal = IdealPrototype();
  const ToleranceModel model(ideal.scene, ideal.designed, Spec({{"gap", "0.1 mm"}}));
  const DisplaySystem nominal = model.Compile(model.Zero());
  for (const VirtualLayer& l : ideal.designed.layers) {
    EXPECT_NEAR(Named(nominal, l.name).diopters, l.diopters, 1e-12) << l.name;
    EXPECT_NEAR(Named(nominal, l.name).transfer.b, l.transfer.b, 1e-15) << l.name;
  }
  EXPECT_TRUE(model.Perturbed(model.Zero())["elements"][3].contains("distance"));
  EXPECT_FALSE(model.Perturbed(model.Zero())["elements"][3].contains("virtual_depth"));
}

// A panel decentred by d: every ray lands d / pitch pixels from where it did.
TEST(ToleranceMisregistration, ADecentredPanelShiftsByDecentreOverPitch) {
  const Ideal& ideal = IdealPrototype();
  const ToleranceModel model(ideal.scene, ideal.designed, Spec({{"panel_decentre", "0.05 mm"}}));
  const DisplaySystem nominal = model.Compile(model.Zero());
  ToleranceDraw draw = model.Zero();
  draw[DofIndex(model, "panel_decentre rear_a x")] = 0.03e-3;
  draw[DofIndex(model, "panel_decentre rear_a y")] = -0.04e-3;
  const ToleranceResult r = MeasureDraw(model, nominal, draw, nullptr);
  ASSERT_TRUE(r.error.empty()) << r.error;
  const Misregistration& m = LayerOf(r, "rear_a").misregistration;
  EXPECT_EQ(m.rays, 3 * 9 * 25);
  EXPECT_NEAR(m.rms_px, 0.05e-3 / kPitch, 1e-9);
  EXPECT_NEAR(m.max_px, 0.05e-3 / kPitch, 1e-9);
  EXPECT_EQ(LayerOf(r, "front_a").misregistration.max_px, 0.0) << "the other panels stay";
}

// A stack's front panel moved back by delta behind the ideal magnifier: a ray
// of slope s after the lens lands |s| delta further out, on it and on the
// panel behind it (the stack's spacers add up). s = u - (p + u z_lens) / f.
TEST(ToleranceMisregistration, AMovedPanelShiftsEachRayBySlopeTimesTheMove) {
  const Ideal& ideal = IdealPrototype();
  const ToleranceModel model(ideal.scene, ideal.designed, Spec({{"gap", "0.1 mm"}}));
  const DisplaySystem nominal = model.Compile(model.Zero());
  ToleranceDraw draw = model.Zero();
  const double delta = 0.08e-3;
  draw[DofIndex(model, "gap front_a")] = delta;
  const DisplaySystem moved = model.Compile(draw);
  EXPECT_NEAR(Named(moved, "front_a").position_m - Named(nominal, "front_a").position_m, delta, 1e-15);
  EXPECT_NEAR(Named(moved, "rear_a").position_m - Named(nominal, "rear_a").position_m, delta, 1e-15);
  for (const EyeRay& ray : std::vector<EyeRay>{{0, 0, 0.1, 0}, {2e-3, -1e-3, -0.15, 0.05}, {-3e-3, 3e-3, 0.2, -0.1}}) {
    const double s_x = ray.u_x - (ray.p_x + ray.u_x * kEyeRelief) / kFocal;
    const double s_y = ray.u_y - (ray.p_y + ray.u_y * kEyeRelief) / kFocal;
    const double want = std::hypot(s_x, s_y) * delta / kPitch;
    for (const char* panel : {"front_a", "rear_a"}) {
      const Misregistration m =
          MeasureMisregistration(Named(nominal, panel), Named(moved, panel), nominal.eye.channel_wavelengths_m, {ray});
      ASSERT_EQ(m.rays, 3);
      EXPECT_NEAR(m.max_px, want, 1e-9) << panel;
    }
    const Misregistration other = MeasureMisregistration(Named(nominal, "front_b"), Named(moved, "front_b"),
                                                         nominal.eye.channel_wavelengths_m, {ray});
    EXPECT_EQ(other.max_px, 0.0);
  }
}

TEST(ToleranceModelTest, AFocalLengthToleranceScalesTheThinLens) {
  const Ideal& ideal = IdealPrototype();
  const ToleranceModel model(ideal.scene, ideal.designed, Spec({{"focal_length", "2 %"}}));
  ASSERT_EQ(model.dofs().size(), 1u);
  ToleranceDraw draw = {0.015};
  EXPECT_NEAR(model.Perturbed(draw)["elements"][1]["focal_length"].get<double>(), kFocal * 1.015, 1e-15);
  const DisplaySystem s = model.Compile(draw);
  EXPECT_NEAR(s.layers[0].path[0].power_diopters, 1 / (kFocal * 1.015), 1e-9);
}

ToleranceRun Ranked(const nlohmann::json& tolerances) {
  const Ideal& ideal = IdealPrototype();
  const ToleranceModel model(ideal.scene, ideal.designed, Spec(tolerances));
  return RunTolerance(model, model.Compile(model.Zero()), {1, 1}, nullptr);
}

// 0.1 mm of decentre moves every ray 1.2 px; 0.01 mm of gap at most a slope
// of 0.3 times it, 0.03 px; and the other way round with the limits swapped.
TEST(ToleranceSensitivity, TheDominantToleranceIsTheOneThatMovesPixelsMost) {
  const ToleranceRun decentre = Ranked({{"panel_decentre", "0.1 mm"}, {"gap", "0.01 mm"}});
  ASSERT_EQ(decentre.sensitivity.size(), 2u);
  EXPECT_EQ(decentre.sensitivity[DominantByMisregistration(decentre)].kind, ToleranceKind::kPanelDecentre);
  EXPECT_NEAR(WorstRmsPx(decentre.sensitivity[0].plus), std::sqrt(2.0) * 0.1e-3 / kPitch, 1e-9);
  const ToleranceRun gap = Ranked({{"panel_decentre", "0.001 mm"}, {"gap", "1 mm"}});
  EXPECT_EQ(gap.sensitivity[DominantByMisregistration(gap)].kind, ToleranceKind::kGap);
  EXPECT_EQ(DominantByPsnr(gap), -1) << "no PSNR without a probe";
}

TEST(ToleranceReport, StatsOfKnownValues) {
  const SampleStats s = Stats({1, 2, 3, 4, 5, 6, 7, 8, 9, 10, NAN});
  EXPECT_EQ(s.count, 10);
  EXPECT_DOUBLE_EQ(s.mean, 5.5);
  EXPECT_DOUBLE_EQ(s.sd, std::sqrt(82.5 / 9));
  EXPECT_DOUBLE_EQ(s.p90, 9.1);  // at 0.9 x 9 = 8.1 of the sorted values
  EXPECT_DOUBLE_EQ(s.worst, 10);
  EXPECT_DOUBLE_EQ(Stats({30, 20, 25}, Worse::kLower).worst, 20);
  EXPECT_DOUBLE_EQ(Stats({30, 20, 25}, Worse::kLower).p90, 21);
  EXPECT_DOUBLE_EQ(Stats({-3, 1, 2}, Worse::kFartherFromZero).worst, -3);
}

std::string Refusal(const nlohmann::json& object) {
  try {
    ReadToleranceSpec(object, Location{"scene.json", "/tolerance"});
  } catch (const Error& e) {
    return e.what();
  }
  return "accepted";
}

TEST(ToleranceSpecTest, HostileValuesAreRefusedByPointer) {
  EXPECT_EQ(Refusal({{"panel_decentre", "-0.05 mm"}}),
            "scene.json: /tolerance/panel_decentre: a tolerance is a limit either way of the design, given positive; "
            "got \"-0.05 mm\"");
  EXPECT_NE(Refusal({{"gap", "nan mm"}}).find("scene.json: /tolerance/gap: "), std::string::npos);
  EXPECT_NE(Refusal({{"panel_tilt", "0.2 mm"}}).find("scene.json: /tolerance/panel_tilt: "), std::string::npos);
  EXPECT_NE(Refusal({{"focal_length", "1 mm"}}).find("scene.json: /tolerance/focal_length: "), std::string::npos);
  EXPECT_EQ(Refusal({{"gap", "2 cm"}}),
            "scene.json: /tolerance/gap: at most 10 mm (an assembly tolerance, not a redesign); got \"2 cm\"");
  EXPECT_NE(
      Refusal({{"panel_decenter", "0.05 mm"}}).find("unknown key \"panel_decenter\"; did you mean \"panel_decentre\"?"),
      std::string::npos);
  EXPECT_NE(Refusal(nlohmann::json::object()).find("scene.json: /tolerance: no tolerances"), std::string::npos);
  EXPECT_NE(Refusal({1, 2}).find("scene.json: /tolerance: expected an object of tolerances"), std::string::npos);
  EXPECT_NE(Refusal({{"gap", true}}).find("scene.json: /tolerance/gap"), std::string::npos);
  const ToleranceSpec good = Spec({{"focal_length", "1 %"}, {"panel_tilt", "0.2 deg"}});
  ASSERT_EQ(good.tolerances.size(), 2u);
  EXPECT_EQ(good.tolerances[0].kind, ToleranceKind::kPanelTilt) << "in the order of the kinds";
  EXPECT_NEAR(good.tolerances[0].limit, 0.2 * std::numbers::pi / 180, 1e-15);
  EXPECT_NEAR(good.tolerances[1].limit, 0.01, 1e-15);
}

}  // namespace
}  // namespace layerlab
