// A backlight that is not uniform (elements/backlight.cpp): a pinlight array
// and an LED array behind a diffuser, each a layer at the backlight's plane.
// Checked against independent computations: the pinlight's point spread in
// eye space (the retinal image of one pinlight through an open LCD is the
// pupil's disk scaled by the defocus, of second moment (A |D_p - D_a| / 2)^2
// / 4 per axis, holding the pinlight's solid angle pi (r / z_p)^2 at any
// focus); the LED's spread (the seen emission of one LED is the Gaussian of
// its FWHM holding the LED cell's area, in closed form); and the solve,
// which holds each LED value at its site.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <random>

#include "layerlab/framework/exr_image.h"
#include "layerlab/kernels/synthesis.h"
#include "layerlab/metrics/psnr.h"
#include "layerlab/retina/retina.h"
#include "layerlab/solvers/objective.h"
#include "layerlab/solvers/solver.h"
#include "layerlab/systems/source_spread.h"
#include "layerlab/systems/system_report.h"
#include "test_util.h"

namespace layerlab {
namespace {

using layerlab::testing::CompileError;
using layerlab::testing::CompileJson;

// An eye, an LCD of 80 x 80 pixels of 100 um `lcd_depth` from the pupil, and `backlight` behind it.
nlohmann::json Scene(const nlohmann::json& backlight, int pupil_samples = 41) {
  nlohmann::json s = {{"format", "layerlab-scene/1"}, {"name", "emission test"}};
  s["elements"] = nlohmann::json::array();
  s["elements"].push_back({{"type", "eye"},
                           {"name", "eye"},
                           {"pupil_diameter", "4 mm"},
                           {"pupil_shape", "round"},
                           {"pupil_samples", {pupil_samples, pupil_samples}},
                           {"eyebox", {"4 mm", "4 mm"}},
                           {"views", {5, 5}},
                           {"next", "lcd"}});
  s["elements"].push_back({{"type", "lc_panel"},
                           {"name", "lcd"},
                           {"virtual_depth", "25 mm"},
                           {"pixel_pitch", "100 um"},
                           {"resolution", {80, 80}},
                           {"next", "light"}});
  nlohmann::json b = backlight;
  b["type"] = "backlight", b["name"] = "light", b["luminance"] = "1000 cd/m2";
  s["elements"].push_back(b);
  return s;
}

nlohmann::json OnePinlight() {
  return {{"gap", "10 mm"}, {"pinlights", {{"pitch", "2 mm"}, {"diameter", "0.1 mm"}, {"count", {1, 1}}}}};
}

nlohmann::json Leds() {
  return {{"gap", "5 mm"}, {"leds", {{"pitch", "1 mm"}, {"count", {9, 9}}, {"spread_fwhm", "1.5 mm"}}}};
}

TEST(BacklightEmission, APinlightArrayIsAFixedLayerAtItsGap) {
  const DisplaySystem system = CompileJson(
      Scene({{"gap", "10 mm"}, {"pinlights", {{"pitch", "2 mm"}, {"diameter", "0.1 mm"}, {"count", {3, 2}}}}}));
  ASSERT_EQ(system.layers.size(), 2u);
  const VirtualLayer& light = system.layers[0];
  EXPECT_EQ(light.name, "light");
  EXPECT_NEAR(light.position_m, 0.035, 1e-15);
  EXPECT_NEAR(light.diopters, 1 / 0.035, 1e-9);
  ASSERT_TRUE(light.panel.emitter && light.panel.fixed_pattern);
  EXPECT_FALSE(light.panel.emitter->solved());
  // 0.1 mm / 4 = 25 um pixels: 80 per 2 mm cell.
  EXPECT_EQ(light.cols, 240);
  EXPECT_EQ(light.rows, 160);
  EXPECT_NEAR(light.panel.pitch_x_m, 25e-6, 1e-18);
  // Each pinlight holds pi r^2 of light; its centre pixel is lit, a cell's corner dark.
  const std::vector<float>& p = *light.panel.fixed_pattern;
  double sum = 0;
  for (size_t k = 0; k < p.size(); k += 3) sum += p[k];
  const double h = light.panel.pitch_x_m, r = 0.05e-3;
  EXPECT_NEAR(sum * h * h / 6, std::numbers::pi * r * r, 0.005 * std::numbers::pi * r * r);
  EXPECT_EQ(p[(40 * 240 + 40) * 3], 1.0f);
  EXPECT_EQ(p[(0 * 240 + 0) * 3], 0.0f);
  EXPECT_EQ(p[(80 * 240 + 120) * 3], 0.0f);
  // The light field and the system's resolution are the LCD's, not the emission grid's.
  EXPECT_EQ(DisplayLightFieldGeometry(system).cols, 80);
  EXPECT_NEAR(system.max_cpd, system.layers[1].max_cpd, 0);
  EXPECT_NE(FormatSystemTable(system).find("light emits an array of 3 x 2 pinlights 0.100 mm wide, 2.00 mm apart, "
                                           "lighting 0.20 % of their plane: the solve leaves it as it is"),
            std::string::npos)
      << FormatSystemTable(system);
}

// An emission image is a fixed layer of its own pixels and pitch, the file's values as they are.
TEST(BacklightEmission, AnEmissionImageIsAFixedLayerOfItsPixels) {
  const std::string folder = ::testing::TempDir() + "layerlab_emission_image";
  std::filesystem::create_directories(folder);
  Image image;
  image.width = 8, image.height = 4, image.channels = {"Y"};
  for (int k = 0; k < 32; ++k) image.pixels.push_back(k / 32.0f);
  WriteExr(folder + "/glow.exr", image);
  const DisplaySystem system =
      CompileJson(Scene({{"gap", "4 mm"}, {"pattern", {{"file", "glow.exr"}, {"pixel_pitch", {"1 mm", "2 mm"}}}}}),
                  folder + "/scene.json");
  const VirtualLayer& light = system.layers[0];
  EXPECT_NEAR(light.position_m, 0.029, 1e-15);
  EXPECT_EQ(light.cols, 8);
  EXPECT_EQ(light.rows, 4);
  EXPECT_EQ(light.panel.pitch_y_m, 2e-3);
  ASSERT_TRUE(light.panel.fixed_pattern);
  for (int k = 0; k < 32; ++k)
    for (int c = 0; c < 3; ++c) ASSERT_EQ((*light.panel.fixed_pattern)[k * 3 + c], k / 32.0f);
  image.pixels[3] = 2.0f;
  WriteExr(folder + "/hot.exr", image);
  const std::string e = testing::ErrorOf([&] {
    CompileJson(Scene({{"gap", "4 mm"}, {"pattern", {{"file", "hot.exr"}, {"pixel_pitch", "1 mm"}}}}),
                folder + "/scene.json");
  });
  EXPECT_NE(e.find("/elements/2/pattern/file: " + folder +
                   "/hot.exr: pixel (row 0, col 3) holds 2.000000, outside "
                   "the emission range [0, 1]"),
            std::string::npos)
      << e;
}

// One pinlight on the axis behind an open LCD, seen by an eye focused at
// 2 D: its retinal image is the round pupil scaled by |D_p - D_a| (radius
// R = A/2 |D_p - D_a| in tan units), blurred by the pinlight's own disk
// (radius rho = r / z_p): second moment (R^2 + rho^2) / 4 per axis, and it
// holds pi rho^2 (the solid angle of the pinlight) at any focus.
TEST(BacklightEmission, APinlightsPointSpreadInEyeSpaceIsThePupilScaledByTheDefocus) {
  const DisplaySystem system = CompileJson(Scene(OnePinlight()));
  const DisplayModel model(system, DisplayLightFieldGeometry(system), Sampling::kBilinear);
  Patterns t = InitialPatterns(model, SolverOptions{});
  std::fill(t[1].rgb.begin(), t[1].rgb.end(), 1.0f);  // the LCD open
  const double z_p = 0.035, rho = 0.05e-3 / z_p, A = 4e-3;
  for (const double focus : {2.0, 10.0}) {
    const double R = A / 2 * std::abs(1 / z_p - focus);
    const double resolution = 0.04 * std::numbers::pi / 180;
    const RetinaGrid grid = MakeRetinaGrid(2.6 * R, 2.6 * R, resolution);
    const Image image = RetinaOfDisplay(model, t, grid, PupilSamples(system.eye), {focus, focus, focus});
    double mass = 0, mx = 0, my = 0, mxx = 0, myy = 0;
    for (int i = 0; i < grid.rows; ++i)
      for (int j = 0; j < grid.cols; ++j) {
        const double ax = grid.angle_x(j), ay = grid.angle_y(i);
        // The sample's area in tan units: d tan = sec^2 a da.
        const double w = image.pixels[(size_t(i) * grid.cols + j) * 3 + 1] * resolution * resolution /
                         (std::cos(ax) * std::cos(ax) * std::cos(ay) * std::cos(ay));
        const double x = std::tan(ax), y = std::tan(ay);
        mass += w, mx += w * x, my += w * y, mxx += w * x * x, myy += w * y * y;
      }
    SCOPED_TRACE("focus " + std::to_string(focus) + " D");
    EXPECT_NEAR(mass, std::numbers::pi * rho * rho, 0.01 * std::numbers::pi * rho * rho);
    EXPECT_NEAR(mx / mass, 0, 1e-3 * R);
    EXPECT_NEAR(my / mass, 0, 1e-3 * R);
    const double expected = (R * R + rho * rho) / 4;
    EXPECT_NEAR(mxx / mass, expected, 0.02 * expected);
    EXPECT_NEAR(myy / mass, expected, 0.02 * expected);
  }
}

// The seen emission of one LED is the closed-form Gaussian of its FWHM, holding its cell's area:
// B(x, y) = p^2 / (2 pi sigma^2) exp(-(x^2 + y^2) / (2 sigma^2)); LEDs all at 1 emit 1 between the edges.
// A light field of a pinlight display is dark on most rays: a low PSNR names the pinlights as its cause.
TEST(BacklightEmission, ALowPsnrBehindPinlightsNamesThem) {
  const DisplaySystem system = CompileJson(
      Scene({{"gap", "10 mm"}, {"pinlights", {{"pitch", "2 mm"}, {"diameter", "0.1 mm"}, {"count", {3, 3}}}}}, 5));
  const DisplayModel model(system, DisplayLightFieldGeometry(system), Sampling::kBilinear);
  LightField target(model.geometry());
  std::fill(target.rgb.begin(), target.rgb.end(), 0.2f);
  SolverOptions options;
  options.iterations = 2;
  Patterns t;
  const SolverReport report = SolverRegistry::Builtins().create("multiplicative")->Solve(model, target, options, &t);
  ASSERT_TRUE(report.IsSolutionUsable()) << report.message;
  const std::optional<std::string> warning = FarBelowWarning(model, report);
  ASSERT_TRUE(warning);
  EXPECT_NE(warning->find("the backlight \"light\" emits on 0.20 % of its plane (an array of 3 x 3 pinlights"),
            std::string::npos)
      << *warning;
}

TEST(BacklightEmission, AnLedsSpreadIsItsGaussianHoldingItsCell) {
  const DisplaySystem system = CompileJson(Scene(Leds()));
  const VirtualLayer& leds = system.layers[0];
  ASSERT_TRUE(IsSolvedEmitter(leds));
  const int stride = leds.panel.emitter->led_stride;
  EXPECT_EQ(stride, 3);  // ceil(4 x 1 mm / 1.5 mm) = 3, odd
  EXPECT_EQ(leds.cols, 27);
  const std::vector<LayerDiffraction> kernels = SeenKernels(system, false);
  ASSERT_EQ(kernels.size(), 1u);
  Patterns one;
  one.emplace_back(leds.cols, leds.rows, 0.0f);
  one.emplace_back(80, 80, 1.0f);
  const int site = 4 * stride + stride / 2;  // the middle LED's centre pixel
  for (int c = 0; c < 3; ++c) one[0].rgb[(size_t(site) * leds.cols + site) * 3 + c] = 1.0f;
  const Patterns seen = DiffractedPatterns(kernels, one);
  const double p = 1e-3, h = p / stride, sigma = 1.5e-3 / (2 * std::sqrt(2 * std::log(2.0)));
  const double peak = p * p / (2 * std::numbers::pi * sigma * sigma);
  const int reach = kernels[0].axes[0][0].reach;  // 4 sigma: beyond, exp(-8) of the peak is cut
  EXPECT_EQ(reach, static_cast<int>(std::ceil(4 * sigma / h)));
  for (int i = 0; i < leds.rows; ++i)
    for (int j = 0; j < leds.cols; ++j) {
      const double x = (j - site) * h, y = (i - site) * h;
      const double expected = peak * std::exp(-(x * x + y * y) / (2 * sigma * sigma));
      const float value = seen[0].rgb[(size_t(i) * leds.cols + j) * 3];
      if (std::abs(i - site) <= reach && std::abs(j - site) <= reach)
        ASSERT_NEAR(value, expected, 1e-4 * peak) << i << ", " << j;  // the cut tail, renormalized
      else
        ASSERT_TRUE(value == 0 && expected < std::exp(-8.0) * peak) << i << ", " << j;
    }
  EXPECT_EQ(seen[1].rgb, one[1].rgb);  // the LCD is not spread

  Patterns all =
      InitialPatterns(DisplayModel(system, DisplayLightFieldGeometry(system), Sampling::kBilinear), SolverOptions{});
  std::fill(all[0].rgb.begin(), all[0].rgb.end(), 1.0f);
  KeepEmitterSites(leds, &all[0].rgb);
  const Patterns lit = DiffractedPatterns(kernels, all);
  for (int i = reach; i < leds.rows - reach; ++i)
    for (int j = reach; j < leds.cols - reach; ++j)
      ASSERT_NEAR(lit[0].rgb[(size_t(i) * leds.cols + j) * 3], 1.0, 2e-3) << i << ", " << j;
}

// The LEDs and the LCD solved together recover a display they could show, and each LED value stays at its
// site (the pixels between hold 0); the solvers that move every pixel refuse the display.
TEST(BacklightEmission, TheMultiplicativeSolveKeepsTheLedsAtTheirSites) {
  const DisplaySystem system = CompileJson(Scene(Leds()));
  const DisplayModel model(system, DisplayLightFieldGeometry(system), Sampling::kBilinear);
  Patterns shown = InitialPatterns(model, SolverOptions{});
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.1f, 1.0f);
  for (LayerPattern& p : shown)
    for (float& v : p.rgb) v = u(rng);
  KeepEmitterSites(system.layers[0], &shown[0].rgb);
  const LightField target = Synthesize(model, DiffractedPatterns(SeenKernels(system, false), shown));

  SolverOptions options;
  options.iterations = 200;
  Patterns t;
  const SolverReport report = SolverRegistry::Builtins().create("multiplicative")->Solve(model, target, options, &t);
  ASSERT_TRUE(report.IsSolutionUsable()) << report.message;
  EXPECT_GT(report.final_psnr_db, 40.0);
  const VirtualLayer& leds = system.layers[0];
  const int stride = leds.panel.emitter->led_stride;
  int sites = 0;
  for (int i = 0; i < leds.rows; ++i)
    for (int j = 0; j < leds.cols; ++j)
      for (int c = 0; c < 3; ++c) {
        const float v = t[0].rgb[(size_t(i) * leds.cols + j) * 3 + c];
        if (i % stride == stride / 2 && j % stride == stride / 2)
          sites += v > 0;
        else
          ASSERT_EQ(v, 0.0f) << i << ", " << j;
      }
  EXPECT_EQ(sites, 9 * 9 * 3);
  const LayerPattern values = LedValues(leds, t[0]);  // one pixel per LED, the site's value
  ASSERT_EQ(values.cols, 9);
  EXPECT_EQ(values.rgb[(2 * 9 + 5) * 3 + 1], t[0].rgb[((2 * stride + 1) * leds.cols + 5 * stride + 1) * 3 + 1]);

  Patterns refused;
  const SolverReport qn = SolverRegistry::Builtins().create("quasi-newton")->Solve(model, target, options, &refused);
  EXPECT_FALSE(qn.IsSolutionUsable());
  EXPECT_NE(qn.message.find("layer light emits an array of 9 x 9 LEDs 1.00 mm apart, each spread over 1.50 mm (FWHM), "
                            "solved only at its LEDs, which the quasi-newton solver would change: solve this display "
                            "with the multiplicative solver"),
            std::string::npos)
      << qn.message;
}

TEST(BacklightEmission, AWrongBacklightIsRefusedNamingWhy) {
  nlohmann::json both = Leds();
  both["pinlights"] = OnePinlight()["pinlights"];
  EXPECT_NE(CompileError(Scene(both))
                .find("/elements/2/leds: a backlight emits one pattern: give one of "
                      "\"pattern\", \"pinlights\" and \"leds\", not both \"pinlights\" and "
                      "\"leds\""),
            std::string::npos)
      << CompileError(Scene(both));
  nlohmann::json no_gap = Leds();
  no_gap.erase("gap");
  EXPECT_NE(CompileError(Scene(no_gap)).find("give its \"gap\" from the panel in front"), std::string::npos)
      << CompileError(Scene(no_gap));
  EXPECT_NE(CompileError(Scene({{"gap", "5 mm"}})).find("/elements/2/gap: a uniform backlight's place"),
            std::string::npos)
      << CompileError(Scene({{"gap", "5 mm"}}));
  nlohmann::json sharp = Leds();
  sharp["leds"]["spread_fwhm"] = "0.05 mm";
  EXPECT_NE(CompileError(Scene(sharp)).find("/elements/2/leds/spread_fwhm: must lie in 0.121 mm to 16.000 mm"),
            std::string::npos)
      << CompileError(Scene(sharp));
  nlohmann::json wide = OnePinlight();
  wide["pinlights"]["diameter"] = "3 mm";
  EXPECT_NE(CompileError(Scene(wide)).find("/elements/2/pinlights/diameter"), std::string::npos)
      << CompileError(Scene(wide));
  nlohmann::json fine = OnePinlight();
  fine["pinlights"]["diameter"] = "1 um";
  fine["pinlights"]["count"] = {50, 50};
  EXPECT_NE(CompileError(Scene(fine)).find("its emission would need a grid of 400000 x 400000 pixels"),
            std::string::npos)
      << CompileError(Scene(fine));
  fine["pinlights"]["diameter"] = 1e-18;  // m: more pixels than an integer holds, refused before they are counted
  EXPECT_NE(CompileError(Scene(fine)).find("its emission would need a grid of"), std::string::npos)
      << CompileError(Scene(fine));
}

}  // namespace
}  // namespace layerlab
