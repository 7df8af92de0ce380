// The accommodation analysis off the axis (ContrastOptions::field_center_deg)
// and with patterns solved for another display (RunContrast's
// factorized_for), against what a known grating and a perfect display must give.
#include <cmath>
#include <numbers>

#include "layerlab/analysis/contrast.h"
#include "layerlab/framework/units.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

// The multiplicative example's rear panel alone, at `diopters`: a display
// that can show the sampled target exactly; `reversed`: the panel mounted back
// to front; `real_lens`: behind Thorlabs LA1608 (examples/paper_prototype_la1608.json's), traced exactly.
ContrastDisplay OneLayerAt(double diopters, const std::string& name = "one_layer", bool reversed = false,
                           bool real_lens = false) {
  nlohmann::json scene = testing::ReadExample("multiplicative_2layer.json");
  testing::ElementNamed(scene, "lens")["next"] = "rear";
  scene["elements"].erase(2);
  testing::ElementNamed(scene, "rear")["virtual_depth"] = std::to_string(diopters) + " D";
  testing::ElementNamed(scene, "rear")["reversed"] = reversed;
  if (real_lens)
    testing::ElementNamed(scene, "lens") = {
        {"type", "lens"},
        {"name", "lens"},
        {"clear_aperture", "25.4 mm"},
        {"surfaces",
         {{{"radius", "38.6 mm"}, {"material", "N-BK7"}, {"thickness", "4.1 mm"}}, nlohmann::json::object()}},
        {"next", "rear"}};
  ContrastDisplay d;
  d.name = name;
  d.system = testing::CompileJson(scene);
  d.solver = "multiplicative";
  return d;
}

// Vertical bars of `cpd` uniform in visual angle a (degrees, seen from the
// pupil's centre), 0.5 (1 + m(a) cos(2 pi f a)), whose contrast m is 0.2 left
// of the axis and 0.8 right of it: what an analysed window sees depends on where it is.
class SidedGrating : public Texture {
 public:
  SidedGrating(double depth_m, double cpd) : depth_m_(depth_m), cpd_(cpd) {}
  Rgb Evaluate(double s, double) const override {
    const double a = std::atan(s / depth_m_) / kRadiansPerDegree;
    const float v = static_cast<float>(0.5 * (1 + (a < 0 ? 0.2 : 0.8) * std::cos(2 * std::numbers::pi * cpd_ * a)));
    return {v, v, v};
  }
  std::string Describe() const override { return "sided grating"; }
  bool ConstantAlongT() const override { return true; }

 private:
  double depth_m_, cpd_;
};

PlaneTextureFactory Sided() {
  return [](double depth, double cpd) { return std::make_shared<SidedGrating>(depth, cpd); };
}

const ContrastCurve& Curve(const std::vector<ContrastCurve>& curves, const std::string& display) {
  for (const ContrastCurve& c : curves)
    if (c.display == display) return c;
  throw Error("no curve " + display);
}

ContrastOptions OffAxis(double dt, double field_center_deg) {
  ContrastOptions o;
  o.target_diopters = {dt};
  o.frequencies_cpd = {3.0};
  o.accommodation_min_diopters = dt - 0.3, o.accommodation_max_diopters = dt + 0.3;
  o.accommodation_step_diopters = 0.1;
  o.retina_field_deg = 4, o.retina_resolution_deg = 0.02;
  o.field_center_deg = field_center_deg;
  o.strip_rows = 6;
  o.peak_uncertainty = false;
  return o;
}

// In focus every pupil ray of the retinal sample at angle a meets the plane
// at a: the retinal row is the texture's, and its Fourier amplitude at f over
// whole cycles of the window from 10 to 14 deg is 0.5 * 0.8 = 0.4 (the right
// side's), where the centred window straddles both sides (0.5 * 0.5 = 0.25).
TEST(ContrastOffAxis, TheWindowAndItsReferenceMoveToTheFieldCentre) {
  const double dt = 1.3;
  ContrastOptions o = OffAxis(dt, 12);
  o.texture = Sided();
  o.reference = ContrastReference::kContinuous;
  const ContrastDisplay d = OneLayerAt(dt);
  EXPECT_NEAR(Curve(RunContrast({d}, o), "natural").reference_amplitude, 0.4, 2e-3);
  o.field_center_deg = -12;
  EXPECT_NEAR(Curve(RunContrast({d}, o), "natural").reference_amplitude, 0.1, 2e-3);
  o.field_center_deg = 0;
  EXPECT_NEAR(Curve(RunContrast({d}, o), "natural").reference_amplitude, 0.25, 5e-3);
}

// Natural viewing is 1 at D_t off the axis as on it, and a display that can
// show its target exactly peaks at D_t there too, near 1 (the sampled reference).
TEST(ContrastOffAxis, APerfectDisplayPeaksAtTheTargetTwelveDegreesOffAxis) {
  const double dt = 1.3;
  for (double at : {12.0, -12.0}) {
    const std::vector<ContrastCurve> curves = RunContrast({OneLayerAt(dt)}, OffAxis(dt, at));
    EXPECT_NEAR(Curve(curves, "natural").at_target, 1.0, 1e-6) << at << " deg";
    const ContrastCurve& display = Curve(curves, "one_layer");
    EXPECT_NEAR(display.peak.at_grid, dt, 1e-9) << at << " deg";
    EXPECT_NEAR(display.at_target, 1.0, 0.01) << at << " deg";
  }
}

TEST(ContrastOffAxis, AWindowBeyondTheDisplaysFieldIsRefusedNamingTheOption) {
  const ContrastDisplay d = OneLayerAt(1.3);
  const double edge = 0.5 * d.system.fov_x_rad / kRadiansPerDegree;
  ContrastOptions o = OffAxis(1.3, edge - 2.05);  // the window's right side 0.05 deg inside the field's edge
  EXPECT_EQ(ContrastDisplayProblem({d}, o), "");
  o.field_center_deg = edge - 1.9;
  const std::string why = ContrastDisplayProblem({d}, o);
  EXPECT_EQ(why.rfind("field_center: ", 0), 0u) << why;
  EXPECT_NE(why.find("leaves the field of one_layer, " + FormatFixed(-edge, 2) + " to " + FormatFixed(edge, 2)),
            std::string::npos)
      << why;
  EXPECT_THROW(RunContrast({d}, o), Error);
  o.field_center_deg = -(edge - 1.9);
  EXPECT_NE(ContrastDisplayProblem({d}, o), "");
  // And the range of the table, whatever the display: 80 deg at most, and a number.
  for (double hostile : {81.0, -81.0, std::nan("")}) {
    o.field_center_deg = hostile;
    std::string range;
    EXPECT_FALSE(o.IsValid(&range)) << hostile;
    EXPECT_EQ(range.rfind("field_center: ", 0), 0u) << range;
  }
}

// Factorized for itself, a display's second curve is its own, bit for bit.
TEST(ContrastFactorizedFor, ADisplayFactorizedForItselfIsItsOwnCurve) {
  ContrastDisplay d;
  d.name = "multiplicative_2layer";
  d.system = testing::CompileJson(testing::ReadExample("multiplicative_2layer.json"));
  d.solver = "multiplicative";
  d.options.iterations = 8;
  d.options_given = true;
  ContrastOptions o = OffAxis(1.3, 6);
  o.target_diopters = {0.7, 1.9};
  o.peak_uncertainty = true;
  const std::vector<ContrastCurve> curves = RunContrast({d}, o, &d);
  int pairs = 0;
  for (const ContrastCurve& own : curves) {
    if (own.display != d.name) continue;
    for (const ContrastCurve& seen : curves)
      if (seen.display == "multiplicative_2layer (factorized for multiplicative_2layer)" &&
          seen.target_diopters == own.target_diopters) {
        EXPECT_EQ(seen.factorized_for, d.name);
        EXPECT_EQ(seen.contrast, own.contrast) << own.target_diopters << " D";
        EXPECT_EQ(seen.contrast_shifted, own.contrast_shifted) << own.target_diopters << " D";
        EXPECT_EQ(seen.psnr_db, own.psnr_db);
        ++pairs;
      }
  }
  EXPECT_EQ(pairs, 2);
}

// The same panel mounted reversed solves the sided grating mirrored on it;
// seen through the unreversed display the eye finds, 12 deg to the right, the
// left side's contrast, 0.2 where natural viewing has 0.8: a quarter of its
// own curve at the target. Through ideal optics (the one-tap retina) and
// through a real singlet (the general path, where the display's own model
// traces its rays), which is symmetric about the axis as the mirror is; at
// 4 deg there, since 12 deg off axis its field curvature (about -1 D) leaves
// one layer little contrast to compare.
TEST(ContrastFactorizedFor, PatternsSolvedForAMirroredPanelShowTheOtherSide) {
  const double dt = 1.3;
  for (bool real_lens : {false, true}) {
    SCOPED_TRACE(real_lens ? "behind LA1608, 4 deg" : "behind the ideal lens, 12 deg");
    ContrastOptions o = OffAxis(dt, real_lens ? 4 : 12);
    o.texture = Sided();
    const ContrastDisplay mirrored = OneLayerAt(dt, "mirrored", true, real_lens);
    const std::vector<ContrastCurve> curves =
        RunContrast({OneLayerAt(dt, "one_layer", false, real_lens)}, o, &mirrored);
    const ContrastCurve& own = Curve(curves, "one_layer");
    EXPECT_NEAR(own.at_target, 1.0, real_lens ? 0.1 : 0.01);
    const ContrastCurve& seen = Curve(curves, "one_layer (factorized for mirrored)");
    EXPECT_EQ(seen.factorized_for, "mirrored");
    EXPECT_NEAR(seen.at_target / own.at_target, 0.25, 0.01);
    EXPECT_NEAR(seen.peak.at_grid, own.peak.at_grid, 1e-9);  // a one-layer image is sharpest at its layer
  }
}

TEST(ContrastFactorizedFor, LayersThatDoNotMatchAreRefused) {
  const ContrastDisplay one = OneLayerAt(1.3);
  ContrastDisplay two;
  two.name = "multiplicative_2layer";
  two.system = testing::CompileJson(testing::ReadExample("multiplicative_2layer.json"));
  const ContrastOptions o = OffAxis(1.3, 0);
  std::string why = ContrastDisplayProblem({one}, o, &two);
  EXPECT_EQ(why,
            "factorized_for: multiplicative_2layer: its patterns cannot be shown on one_layer: 2 layers against 1");
  EXPECT_THROW(RunContrast({one}, o, &two), Error);

  nlohmann::json scene = testing::ReadExample("multiplicative_2layer.json");
  testing::ElementNamed(scene, "lens")["next"] = "rear";
  scene["elements"].erase(2);
  testing::ElementNamed(scene, "rear")["virtual_depth"] = "1.3 D";
  testing::ElementNamed(scene, "rear")["active_region"] = {{"cols", 400}, {"rows", 199}};
  ContrastDisplay coarser;
  coarser.name = "coarser";
  coarser.system = testing::CompileJson(scene);
  why = ContrastDisplayProblem({one}, o, &coarser);
  EXPECT_EQ(why,
            "factorized_for: coarser: its patterns cannot be shown on one_layer: layer 0 (rear) has 400 x 199 pixels "
            "against 400 x 200 (rear)");
  EXPECT_EQ(ContrastDisplayProblem({one}, o, &one), "");
}

}  // namespace
}  // namespace layerlab
