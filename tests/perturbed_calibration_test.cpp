// The documented calibration loop on a perturbed prototype (issue 43): the
// paper prototype built with its magnifier 0.5, 2 and 5 % off its catalogue
// focal length, every panel moved, offset, turned and of its own gamma; and
// a real plano-convex magnifier, traced, as designed and 2 % off its surfaces,
// whose distortion the first-order model names as its error. Photographs rendered by the project's own
// renderer, detected, fitted with the default options: every parameter within
// 3 reported standard deviations of the truth, or the result refused naming
// the model error; never a usable result with a parameter beyond 5.
// A CI end-to-end test (e2e.*): several seconds of rendering per case.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "layerlab/calibration/calibration.h"
#include "layerlab/calibration/capture_plan.h"
#include "layerlab/calibration/photo_detection.h"
#include "layerlab/calibration/synthetic_photo.h"
#include "layerlab/framework/exr_image.h"
#include "layerlab/framework/json_file.h"
#include "layerlab/framework/units.h"
#include "layerlab/tests/photo_test_util.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

using testing::PanelTruth;

struct Truth {
  std::string element, quantity;
  double value;
};

// Photographs of `built` for the plan of `designed` (luminance steps at 9 levels when asked), detected.
Measurements Photographed(const DisplaySystem& designed, const DisplaySystem& built, bool luminance,
                          int supersampling) {
  CapturePlan plan = PlanCaptures(designed, testing::TestPlan());
  if (!luminance)
    std::erase_if(plan.captures, [](const PlannedCapture& c) { return c.kind == CaptureKind::kLuminance; });
  PhotoCamera camera = testing::TestCamera();
  camera.supersampling = supersampling;
  plan.camera = camera.intrinsics;
  const PhotoRenderer renderer(camera);
  const std::filesystem::path folder = testing::FreshFolder("perturbed");
  for (size_t k = 0; k < plan.captures.size(); ++k)
    WriteExr((folder / plan.captures[k].photo).string(), renderer.Render(built, plan, plan.captures[k], k),
             ExrCompression::kNone);
  const Detection d = DetectCaptures(folder.string(), plan, designed, std::nullopt);
  std::filesystem::remove_all(folder);
  for (const PhotoFailure& f : d.failures) ADD_FAILURE() << f.photo << ": " << f.reason;
  return d.measurements;
}

// With no focal length (0), the lens is its surfaces: traced, not fitted.
std::vector<Truth> TruthOf(const DisplaySystem& built, const std::vector<PanelTruth>& panels, double focal_length,
                           bool luminance) {
  std::vector<Truth> truth;
  if (focal_length > 0) truth.push_back({"lens", "focal_length", focal_length});
  for (const VirtualLayer& layer : built.layers) {
    truth.push_back({layer.name, "distance", layer.panel_distance_m});
    truth.push_back({layer.name, "virtual_depth", layer.diopters});
    truth.push_back({layer.name, "offset_x", layer.panel.eye_from_panel_m[0]});
    truth.push_back({layer.name, "offset_y", layer.panel.eye_from_panel_m[1]});
    truth.push_back({layer.name, "rotation", layer.panel.rotation_rad});
  }
  if (luminance)
    for (const PanelTruth& p : panels) {
      truth.push_back({p.name, "gamma", p.gamma});
      truth.push_back({p.name, "black_level", p.black_level});
    }
  return truth;
}

// Recovered within 3 sigma (gamma and black level 5), or refused naming the model error. Prints the table.
void ExpectRecoveredOrRefused(const std::string& name, const CalibrationReport& report,
                              const std::vector<Truth>& truth) {
  std::printf("%s: %s\n  %-8s %-13s %14s %14s %12s %7s\n", name.c_str(), report.BriefReport().c_str(), "element",
              "quantity", "truth", "recovered", "sigma", "z");
  double worst = 0;
  for (const Truth& t : truth) {
    const ParameterEstimate* p = report.find(t.element, t.quantity);
    ASSERT_NE(p, nullptr) << name << ": " << t.element << " " << t.quantity;
    if (!p->std_dev) {
      ADD_FAILURE() << name << ": " << t.element << " " << t.quantity << " has no standard deviation ("
                    << ToString(p->status) << ")";
      continue;
    }
    const double z = (p->value - t.value) / *p->std_dev;
    std::printf("  %-8s %-13s %14.8g %14.8g %12.3g %+7.2f\n", t.element.c_str(), t.quantity.c_str(), t.value, p->value,
                *p->std_dev, z);
    // The black levels read high by the other branch's light through its black panels (black x black, some
    // 3e-5 of full white, which the luminance model leaves out): up to 3.2 sigma; photometry is held to 5.
    const bool photometry = t.quantity == "gamma" || t.quantity == "black_level";
    worst = std::max(worst, std::abs(z) * (photometry ? 3.0 / 5.0 : 1.0));
  }
  if (report.IsSolutionUsable()) {
    EXPECT_LE(worst, 3.0) << name << ": a usable calibration with a parameter off by more than 3 sigma (5 for "
                          << "photometry)";
  } else {
    EXPECT_NE(report.message.find("model error"), std::string::npos)
        << name << ": refused, but not for a model error: " << report.message;
  }
}

TEST(PerturbedPrototype, TheDefaultFitRecoversAFocalLengthOffItsCatalogueValue) {
  const DisplaySystem designed = testing::Example("paper_prototype.json");
  const std::vector<PanelTruth> panels = testing::ExampleTruth();
  for (const double off : {0.005, 0.02, 0.05}) {
    const double focal_length = 75e-3 * (1 + off);
    const bool luminance = off == 0.02;
    const DisplaySystem built = testing::Built(designed, panels, {{"lens", 0.0, focal_length}});
    CalibratedDisplay display;
    const CalibrationReport report =
        Calibrate(designed, Photographed(designed, built, luminance, 3), CalibrationOptions{}, &display);
    EXPECT_TRUE(report.noise_from_detection);
    ExpectRecoveredOrRefused("focal length " + FormatFixed(100 * off, 1) + " % off", report,
                             TruthOf(built, panels, focal_length, luminance));
  }
}

// A real magnifier (Thorlabs LA1608), which the fit traces through its
// surfaces. Built as designed, the perturbed panels are recovered within 3
// sigma. Built with its radius 2 % long (and so its focal length), the lens is
// not what its surfaces in the scene say: recovered or refused for the model
// error, which offers no focal length or distortion to fit (the surfaces have
// them). The same photographs fitted by the first-order model (the magnifier
// as an ideal lens): its distortion is the model error, and fitted, it is what
// an exact trace of LA1608 gives apart from layerlab.
TEST(PerturbedPrototype, ARealMagnifierIsTracedWhereTheFirstOrderModelNamesItsDistortion) {
  const DisplaySystem designed = testing::Example("paper_prototype_la1608.json");
  const std::vector<PanelTruth> panels = testing::ExampleTruth();
  const DisplaySystem as_designed = testing::Built(designed, panels);
  CalibratedDisplay display;
  const CalibrationReport traced =
      Calibrate(designed, Photographed(designed, as_designed, false, 2), CalibrationOptions{}, &display);
  EXPECT_TRUE(traced.IsSolutionUsable()) << traced.FullReport();
  ExpectRecoveredOrRefused("LA1608 as designed, traced", traced, TruthOf(as_designed, panels, 0, false));

  nlohmann::json scene = testing::BuiltScene(designed, panels);
  testing::ElementNamed(scene, "lens")["surfaces"][0]["radius"] = "39.372 mm";
  const DisplaySystem built = testing::CompileJson(scene, designed.file);
  const Measurements photographed = Photographed(designed, built, false, 2);
  const CalibrationReport off = Calibrate(designed, photographed, CalibrationOptions{}, &display);
  ExpectRecoveredOrRefused("LA1608 2 % off its surfaces, traced", off, TruthOf(built, panels, 0, false));
  EXPECT_FALSE(off.IsSolutionUsable()) << "docs/calibration.md's table: refused as a model error";
  EXPECT_EQ(off.message.find("--distortion fit"), std::string::npos) << off.message;
  EXPECT_EQ(off.message.find("--focal-length fit"), std::string::npos) << off.message;

  // The first-order model: the scene with the magnifier as an ideal lens of its catalogue focal length.
  nlohmann::json first_order = ReadJsonFile(designed.file);
  nlohmann::json& lens = testing::ElementNamed(first_order, "lens");
  lens = {{"type", "thin_lens"},
          {"name", "lens"},
          {"focal_length", "75 mm"},
          {"clear_aperture", "25.4 mm"},
          {"next", lens["next"]}};
  const DisplaySystem ideal = testing::CompileJson(first_order, designed.file);
  const CalibrationReport report = Calibrate(ideal, photographed, CalibrationOptions{}, &display);
  std::printf("%s\n", report.message.c_str());
  EXPECT_FALSE(report.IsSolutionUsable());
  EXPECT_NE(report.message.find("model error"), std::string::npos) << report.message;
  EXPECT_NE(report.message.find("--distortion fit"), std::string::npos) << report.message;

  // Fitted, the lens's distortion is what an exact trace of LA1608 gives apart from layerlab (issue 42: 2.8 % at
  // the 17.75 deg edge of its field, k = 0.028 / tan^2(17.75 deg) = 0.273); what is left (the field curvature, the
  // aberrations that differ across the camera's positions) is still a model error.
  CalibrationOptions distortion;
  distortion.distortion = FitChoice::kFit;
  const CalibrationReport fitted = Calibrate(ideal, photographed, distortion, &display);
  const ParameterEstimate* k = fitted.find("lens", "distortion");
  ASSERT_TRUE(k && k->std_dev) << fitted.FullReport();
  const double expected = 0.028 / std::pow(std::tan(17.75 * kRadiansPerDegree), 2);
  std::printf("distortion k = %.4f +- %.4f (an independent trace: %.4f); %s\n", k->value, *k->std_dev, expected,
              fitted.BriefReport().c_str());
  EXPECT_NEAR(k->value, expected, 0.1 * expected);
  EXPECT_LT(fitted.variance_ratio, report.variance_ratio);
}

}  // namespace
}  // namespace layerlab
