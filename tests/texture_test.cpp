// Textures against their formulas: gratings in cycles per degree at the
// plane's depth, checkerboards, seeded noise (and its plane-wave table), image
// sampling, and refusals.
#include <cmath>
#include <cstring>
#include <numbers>

#include <png.h>

#include "layerlab/framework/error.h"
#include "layerlab/framework/exr_image.h"
#include "layerlab/framework/units.h"
#include "layerlab/targets/fast_cos.h"
#include "layerlab/targets/length_or_angle.h"
#include "layerlab/targets/plane_wave_table.h"
#include "layerlab/targets/texture.h"
#include "layerlab/tests/render_test_util.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

using nlohmann::json;
using testing::Close;

std::unique_ptr<Texture> Parse(const json& j, const TextureFrame& frame = {}) {
  Params p(j, {"target.json", "/texture"});
  return ParseTexture(p, frame);
}

std::string ParseError(const json& j, const TextureFrame& frame = {}) {
  try {
    Parse(j, frame);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(TextureTest, GratingFrequencyIsCyclesPerDegreeAtTheReferenceDepth) {
  // 2 cpd at 0.5 m: one degree spans 0.5 * pi / 180 m, so the period is 0.5 * pi / 360 m.
  TextureFrame frame;
  frame.reference_depth_m = 0.5;
  auto grating = Parse({{"type", "grating"}, {"frequency", "2 cpd"}, {"contrast", 0.8}, {"mean", 0.25}}, frame);
  double period = 0.5 * kRadiansPerDegree / 2;
  EXPECT_TRUE(Close(grating->Evaluate(0, 0)[0], 0.25 * 1.8, 0, 1e-12));
  EXPECT_TRUE(Close(grating->Evaluate(period / 2, 0.3)[0], 0.25 * 0.2, 0, 1e-12));
  EXPECT_TRUE(Close(grating->Evaluate(7 * period, -1)[1], 0.25 * 1.8, 0, 1e-9));
  EXPECT_TRUE(Close(grating->Evaluate(period / 4, 0)[2], 0.25, 0, 1e-12));
  EXPECT_TRUE(Close(CyclesPerMeter(2, 0.5), 2 / (0.5 * kRadiansPerDegree), 1e-15));
  EXPECT_EQ(grating->Describe(), "grating 2 cpd");
}

TEST(TextureTest, GratingPhaseAndOrientation) {
  TextureFrame frame;
  frame.reference_depth_m = 1;
  auto grating =
      Parse({{"type", "grating"}, {"frequency", "1 cpd"}, {"phase", "90 deg"}, {"orientation", "90 deg"}}, frame);
  double period = kRadiansPerDegree;
  // Horizontal bars: constant along s; cos(2 pi t / period + 90 deg) = -sin(2 pi t / period).
  EXPECT_TRUE(Close(grating->Evaluate(0.123, 0)[0], 0.5, 0, 1e-12));
  EXPECT_TRUE(Close(grating->Evaluate(0.456, period / 4)[0], 0.0, 0, 1e-12));
  EXPECT_TRUE(Close(grating->Evaluate(0, -period / 4)[0], 1.0, 0, 1e-12));
}

TEST(TextureTest, GratingUniformInVisualAngleIsTheFrequencyAtEveryAngle) {
  // 2 cpd at 0.8 m, orientation 30 deg: along the wave vector the point at
  // angle a from the center (w = z tan a) has phase 2 pi f a, a in degrees.
  TextureFrame frame;
  frame.reference_depth_m = 0.8;
  auto grating =
      Parse({{"type", "grating"}, {"frequency", "2 cpd"}, {"orientation", "30 deg"}, {"uniform", "angle"}}, frame);
  auto plane = Parse({{"type", "grating"}, {"frequency", "2 cpd"}, {"orientation", "30 deg"}}, frame);
  const double o = 30 * kRadiansPerDegree;
  for (double a_deg : {-14.3, -3.1, 0.0, 0.2, 6.55, 12.0}) {
    const double w = 0.8 * std::tan(a_deg * kRadiansPerDegree),
                 along = 0.017;  // along: a shift along the bars changes nothing
    const double s = w * std::cos(o) - along * std::sin(o), t = w * std::sin(o) + along * std::cos(o);
    EXPECT_TRUE(Close(grating->Evaluate(s, t)[0], 0.5 * (1 + std::cos(2 * std::numbers::pi * 2 * a_deg)), 0, 1e-12))
        << a_deg << " deg";
    // Uniform on the plane: the small-angle 2 pi f w / (z pi / 180) instead.
    EXPECT_TRUE(Close(plane->Evaluate(s, t)[0],
                      0.5 * (1 + std::cos(2 * std::numbers::pi * 2 * w / (0.8 * kRadiansPerDegree))), 0, 1e-12));
  }
  EXPECT_EQ(grating->Describe(), "grating 2 cpd in visual angle");
  EXPECT_EQ(ParseError({{"type", "grating"}, {"frequency", "2 cpd"}, {"uniform", "angles"}}, frame).substr(0, 45),
            "target.json: /texture/uniform: \"angles\" is no");
}

TEST(TextureTest, CheckerboardPeriodAsAngleOrLength) {
  TextureFrame frame;
  frame.reference_depth_m = 2;
  auto by_angle =
      Parse({{"type", "checkerboard"}, {"period", "1 deg"}, {"low", 0.1}, {"high", json::array({1, 0.5, 0})}}, frame);
  double half = 2 * kRadiansPerDegree / 2;  // one square
  EXPECT_EQ(by_angle->Evaluate(0.1 * half, 0.1 * half), (Rgb{0.1, 0.1, 0.1}));
  EXPECT_EQ(by_angle->Evaluate(1.1 * half, 0.1 * half), (Rgb{1, 0.5, 0}));
  EXPECT_EQ(by_angle->Evaluate(1.1 * half, 1.1 * half), (Rgb{0.1, 0.1, 0.1}));
  EXPECT_EQ(by_angle->Evaluate(-0.1 * half, 0.1 * half), (Rgb{1, 0.5, 0}));
  auto by_length = Parse({{"type", "checkerboard"}, {"period", "2 cm"}}, frame);
  EXPECT_EQ(by_length->Evaluate(0.009, 0.001)[0], 0.0);
  EXPECT_EQ(by_length->Evaluate(0.011, 0.001)[0], 1.0);
}

TEST(TextureTest, NoiseIsSeededAndHasTheRequestedMeanAndRmsContrast) {
  TextureFrame frame;
  frame.reference_depth_m = 1;
  json spec = {{"type", "noise"}, {"band", {"1 cpd", "4 cpd"}}, {"components", 64}, {"seed", 5}, {"contrast", 0.2},
               {"mean", 0.5}};
  auto a = Parse(spec, frame), b = Parse(spec, frame);
  spec["seed"] = 6;
  auto c = Parse(spec, frame);
  EXPECT_EQ(a->Evaluate(0.01, 0.02), b->Evaluate(0.01, 0.02));
  EXPECT_NE(a->Evaluate(0.01, 0.02), c->Evaluate(0.01, 0.02));
  // Over an area of many periods the sum of unit-variance cosines has mean 0 and RMS 1.
  double sum = 0, sum2 = 0;
  const int n = 400;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      double v = a->Evaluate(i * 0.5e-3, j * 0.5e-3)[0];
      sum += v, sum2 += v * v;
    }
  double mean = sum / (n * n), rms = std::sqrt(sum2 / (n * n) - mean * mean);
  EXPECT_TRUE(Close(mean, 0.5, 0.01));
  EXPECT_TRUE(Close(rms / mean, 0.2, 0.05));
}

TEST(TextureTest, FastCosMatchesTheLibrary) {
  double worst = 0;
  for (double x = -2e4; x < 2e4; x += 0.37) worst = std::max(worst, std::abs(FastCos(x) - std::cos(x)));
  for (double x = -7; x < 7; x += 1e-4) worst = std::max(worst, std::abs(FastCos(x) - std::cos(x)));
  EXPECT_LT(worst, 1e-11);
}

TEST(TextureTest, FastSinMatchesTheLibrary) {
  double worst = 0;
  for (double x = -2e4; x < 2e4; x += 0.37) worst = std::max(worst, std::abs(FastSin(x) - std::sin(x)));
  for (double x = -7; x < 7; x += 1e-4) worst = std::max(worst, std::abs(FastSin(x) - std::sin(x)));
  EXPECT_LT(worst, 1e-11);
}

// The table's angle-sum evaluation against the noise summed here with the library's cosine at the point where
// each view's ray meets the plane: s = v + (x - v) z / z_lf - c.
TEST(TextureTest, PlaneWaveTableIsTheNoiseWhereEachViewsRayMeetsThePlane) {
  TextureFrame frame;
  frame.reference_depth_m = 2.5;
  auto noise = Parse({{"type", "noise"},
                      {"band", {"0.5 cpd", "3 cpd"}},
                      {"components", 48},
                      {"seed", 7},
                      {"contrast", 0.9},
                      {"mean", 0.35}},
                     frame);
  const PlaneWaves* waves = noise->plane_waves();
  ASSERT_NE(waves, nullptr);
  ASSERT_EQ(waves->kx.size(), 48u);
  const double z = 2.5, z_lf = 1.0;
  const std::array<double, 2> centre{0.03, -0.02};
  PlaneWaveTable table(*waves, z, centre, z_lf);
  std::vector<std::array<double, 2>> points;
  for (int i = 0; i < 40; ++i) points.push_back({-0.2 + 0.0107 * i, 0.15 - 0.0071 * i * (i % 3)});
  table.SetPoints(points);
  PlaneWaveTable::ViewPhases phases;
  double worst = 0;
  int clamped = 0;
  for (double vx : {-0.003, 0.0, 0.0027})
    for (double vy : {-0.0031, 0.002}) {
      table.PhasesOfView(vx, vy, &phases);
      for (size_t i = 0; i < points.size(); ++i) {
        const double s = vx + (points[i][0] - vx) * z / z_lf - centre[0];
        const double t = vy + (points[i][1] - vy) * z / z_lf - centre[1];
        double sum = 0;
        for (size_t k = 0; k < waves->kx.size(); ++k)
          sum += std::cos(waves->kx[k] * s + waves->ky[k] * t + waves->phase[k]);
        const double expected = std::max(0.0, 0.35 * (1 + 0.9 * std::sqrt(2.0 / 48) * sum));
        clamped += expected == 0;
        worst = std::max(worst, std::abs(table.Value(i, phases) - expected));
        EXPECT_EQ(noise->Evaluate(s, t)[0], waves->Evaluate(s, t));
      }
    }
  EXPECT_LT(worst, 1e-11);
  EXPECT_GT(clamped, 0) << "no point where the noise clamps at 0";
}

TEST(TextureTest, ExrImageIsSampledBilinearlyBetweenPixelCenters) {
  std::string dir = testing::ScratchDir();
  // 2 x 2 pixels: top row 0 and 1, bottom row 2 and 3 (in R; G = R / 2, B = 1).
  Image image{2, 2, {"R", "G", "B"}, {0, 0, 1, 1, 0.5f, 1, 2, 1, 1, 3, 1.5f, 1}};
  WriteExr(dir + "/four.exr", image);
  TextureFrame frame;
  frame.base_dir = dir;
  frame.default_size_m = {2, 1};  // pixels 1 m wide, 0.5 m tall; centers at s = +-0.5, t = +-0.25
  auto clamp = Parse({{"type", "image"}, {"file", "four.exr"}}, frame);
  EXPECT_EQ(clamp->Evaluate(-0.5, 0.25), (Rgb{0, 0, 1}));
  EXPECT_EQ(clamp->Evaluate(0.5, -0.25), (Rgb{3, 1.5, 1}));
  EXPECT_TRUE(Close(clamp->Evaluate(0, 0)[0], 1.5, 1e-12));
  EXPECT_TRUE(Close(clamp->Evaluate(0.25, 0.25)[0], 0.75, 1e-12));
  EXPECT_TRUE(Close(clamp->Evaluate(5, 5)[0], 1.0, 1e-12));  // clamped to the top right pixel
  auto repeat = Parse({{"type", "image"}, {"file", "four.exr"}, {"size", {"4 m", "2 m"}}, {"wrap", "repeat"}}, frame);
  EXPECT_TRUE(Close(repeat->Evaluate(-1, 0.5)[0], 0, 0, 1e-12));
  EXPECT_TRUE(Close(repeat->Evaluate(-1 + 4, 0.5 - 2)[0], 0, 0, 1e-12));
}

TEST(TextureTest, PngImageIsDecodedToLinearLight) {
  std::string dir = testing::ScratchDir();
  const unsigned char pixels[] = {0, 0, 0, 188, 188, 188, 255, 255, 255};  // 3 x 1, sRGB
  png_image png;
  std::memset(&png, 0, sizeof png);
  png.version = PNG_IMAGE_VERSION;
  png.width = 3;
  png.height = 1;
  png.format = PNG_FORMAT_RGB;
  ASSERT_TRUE(png_image_write_to_file(&png, (dir + "/ramp.png").c_str(), 0, pixels, 0, nullptr));
  TextureFrame frame;
  frame.base_dir = dir;
  frame.default_size_m = {3, 1};
  auto texture = Parse({{"type", "image"}, {"file", "ramp.png"}}, frame);
  EXPECT_EQ(texture->Evaluate(-1, 0)[0], 0.0);
  // sRGB 188/255 is ((188/255 + 0.055) / 1.055)^2.4 = 0.502886 in linear light.
  EXPECT_TRUE(Close(texture->Evaluate(0, 0)[1], 0.502886, 0, 1e-6));
  EXPECT_TRUE(Close(texture->Evaluate(1, 0)[2], 1.0, 0, 1e-6));
}

TEST(TextureTest, RefusesBadSpecificationsWithTheirLocation) {
  EXPECT_EQ(ParseError({{"type", "gratng"}}),
            "target.json: /texture/type: \"gratng\" is not one of constant, grating, checkerboard, noise or image; did "
            "you mean \"grating\"?");
  EXPECT_EQ(ParseError({{"frequency", "2 cpd"}}), "target.json: /texture/type: missing required key \"type\"");
  EXPECT_EQ(ParseError({{"type", "grating"}, {"frequency", "2 cpd"}, {"contrst", 1}}),
            "target.json: /texture/contrst: unknown key \"contrst\"; did you mean \"contrast\"?");
  EXPECT_EQ(ParseError({{"type", "grating"}, {"frequency", "2 deg"}}),
            "target.json: /texture/frequency: 'deg' is an angle unit; expected an angular frequency in cpd");
  EXPECT_EQ(ParseError({{"type", "grating"}, {"frequency", "2 cpd"}, {"contrast", 1.5}}),
            "target.json: /texture/contrast: must be in [0, 1] (SI units), got 1.5");
  EXPECT_EQ(ParseError({{"type", "checkerboard"}, {"period", 0.01}}),
            "target.json: /texture/period: a bare number is ambiguous here; expected a length such as \"12 mm\" or an "
            "angle such as \"1 deg\"");
  EXPECT_EQ(ParseError({{"type", "checkerboard"}, {"period", "2 cpd"}}),
            "target.json: /texture/period: expected a length such as \"12 mm\" or an angle such as \"1 deg\", got "
            "\"2 cpd\"");
  EXPECT_EQ(ParseError({{"type", "noise"}, {"band", {"4 cpd", "1 cpd"}}}),
            "target.json: /texture/band/1: must be in [4, 1000] (SI units), got 1");
  EXPECT_EQ(ParseError({{"type", "image"}, {"file", "picture.tiff"}}),
            "target.json: /texture/file: unknown image format \".tiff\"; expected .exr or .png");
}

}  // namespace
}  // namespace layerlab
