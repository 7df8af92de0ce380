// The registry of retinal-image metrics (metrics/retinal_metrics.h): each
// registered metric is its file's function on the images as the registry
// says it hands them over (checked here against those functions called
// directly on planes made here), PSNR against a hand-computed value, the
// list parsed in the registry's order, and what is refused, named.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "layerlab/framework/error.h"
#include "layerlab/metrics/csf_jnd.h"
#include "layerlab/metrics/foveal_weight.h"
#include "layerlab/metrics/psnr.h"
#include "layerlab/metrics/retinal_metrics.h"
#include "layerlab/metrics/ssim.h"

namespace layerlab {
namespace {

Image Random(int width, int height, unsigned seed, float lo = 0.1f, float hi = 0.9f) {
  Image image{width, height, {"R", "G", "B"}, std::vector<float>(size_t(width) * height * 3)};
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(lo, hi);
  for (float& v : image.pixels) v = u(rng);
  return image;
}

Plane LuminanceOf(const Image& image, double scale) {
  Plane p{image.width, image.height, {}};
  for (size_t k = 0; k < size_t(image.width) * image.height; ++k)
    p.values.push_back(
        scale * (0.2126 * image.pixels[3 * k] + 0.7152 * image.pixels[3 * k + 1] + 0.0722 * image.pixels[3 * k + 2]));
  return p;
}

const RetinalMetric& Named(const std::string& name) {
  for (const RetinalMetric& m : RetinalMetrics())
    if (m.name == name) return m;
  throw std::runtime_error("no metric " + name);
}

TEST(RetinalMetrics, EachIsItsFilesFunctionOnTheImagesAsHandedOver) {
  const Image display = Random(180, 180, 1), reference = Random(180, 180, 2);
  const MetricViewing viewing{0.05, 120.0};
  // PSNR by hand: a uniform error of 0.1 is an MSE of 0.01, 20 dB.
  Image a = Random(16, 8, 3), b = a;
  for (float& v : b.pixels) v += 0.1f;
  EXPECT_NEAR(Named("psnr").score(b, a, viewing), 20.0, 1e-5);
  EXPECT_TRUE(std::isinf(Named("psnr").score(a, a, viewing)));
  EXPECT_EQ(Named("psnr").score(display, reference, viewing), ImagePsnrDb(display, reference));
  EXPECT_EQ(Named("ssim").score(display, reference, viewing),
            Ssim(EncodedLuminance(display), EncodedLuminance(reference), 1.0));
  EXPECT_EQ(Named("ms_ssim").score(display, reference, viewing),
            MsSsim(EncodedLuminance(display), EncodedLuminance(reference), 1.0));
  // The JND reads luminance in cd/m2: the reference first, at the images' sampling, beta 4.
  EXPECT_NEAR(Named("jnd").score(display, reference, viewing),
              CsfJnd(LuminanceOf(reference, 120.0), LuminanceOf(display, 120.0), {0.05, 4.0, nullptr}), 1e-12);
  EXPECT_EQ(Named("jnd").higher_is_better, false);
  EXPECT_EQ(Named("psnr").column, "psnr_db");
}

TEST(RetinalMetrics, TheJndsExponentIsTheUsersAndOneBelowOneIsRefused) {
  const Image display = Random(64, 48, 1), reference = Random(64, 48, 2);
  MetricSettings settings;
  settings.jnd_minkowski_exponent = 2;
  const MetricViewing viewing = MetricViewing::Of(0.05, 120.0, settings);
  const double rms = CsfJnd(LuminanceOf(reference, 120.0), LuminanceOf(display, 120.0), {0.05, 2.0, nullptr});
  EXPECT_NEAR(Named("jnd").score(display, reference, viewing), rms, 1e-12);
  EXPECT_NE(rms, Named("jnd").score(display, reference, {0.05, 120.0}));  // beta 4 pools otherwise
  for (double bad : {0.5, 0.0, -1.0, std::nan("")}) {
    settings.jnd_minkowski_exponent = bad;
    try {
      CheckMetricSettings(settings, "/run/retina/jnd_minkowski_exponent", "/run/retina/fovea");
      FAIL() << bad << " accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("/run/retina/jnd_minkowski_exponent"), std::string::npos) << e.what();
    }
  }
}

TEST(RetinalMetrics, ATransformsRingingBelowBlackCountsAsBlackAndMoreIsRefused) {
  Image display = Random(20, 20, 4), reference = Random(20, 20, 5), black = display;
  for (int c = 0; c < 3; ++c) display.pixels[c] = -0.5f * float(kRingingFloor), black.pixels[c] = 0.0f;
  const MetricViewing viewing{0.05, 100.0};
  EXPECT_EQ(Named("ssim").score(display, reference, viewing), Named("ssim").score(black, reference, viewing));
  for (int c = 0; c < 3; ++c) display.pixels[3 * 25 + c] = -2 * float(kRingingFloor);
  try {
    Named("ssim").score(display, reference, viewing);
    FAIL() << "a luminance far below 0 was taken";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("pixel (1, 5)"), std::string::npos) << e.what();
  }
}

TEST(RetinalMetrics, ListsAreReadInTheRegistrysOrderWithPsnrAlways) {
  auto names = [](const std::vector<const RetinalMetric*>& list) {
    std::string s;
    for (const RetinalMetric* m : list) s += (s.empty() ? "" : ",") + m->name;
    return s;
  };
  EXPECT_EQ(names(ParseRetinalMetrics("jnd, ms_ssim", "--metrics")), "psnr,ms_ssim,jnd");
  EXPECT_EQ(names(ParseRetinalMetrics("psnr", "--metrics")), "psnr");
  EXPECT_EQ(names(ParseRetinalMetrics("", "--metrics")), "psnr");
  EXPECT_EQ(names(ParseRetinalMetrics("all", "--metrics")), "psnr,ssim,ms_ssim,jnd");
  for (const char* bad : {"ssim,lpips", "ssim,ssim", "ssim,"}) {
    try {
      ParseRetinalMetrics(bad, "--metrics");
      FAIL() << bad;
    } catch (const Error& e) {
      EXPECT_EQ(std::string(e.what()).rfind("--metrics: ", 0), 0u) << e.what();
    }
  }
  try {
    CheckMetricSize(ParseRetinalMetrics("ms_ssim", "m"), 400, 120, "retina");
    FAIL() << "MS-SSIM took 120 rows";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("ms_ssim needs images of at least 176 x 176"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(CheckMetricSize(ParseRetinalMetrics("all", "m"), 176, 176, "retina"));
}

}  // namespace
}  // namespace layerlab

namespace layerlab {
namespace {

TEST(FovealWeight, IsTheCorticalAreaRelativeToTheFoveas) {
  EXPECT_DOUBLE_EQ(FovealWeightAt(0), 1.0);
  EXPECT_DOUBLE_EQ(FovealWeightAt(0.75), 0.25);                       // M(e) = 17.3 / (e + 0.75): half, squared
  EXPECT_NEAR(FovealWeightAt(6.75), std::pow(0.75 / 7.5, 2), 1e-15);  // a hundredth
  // Pixel centres 0.5 deg apart on a 4 x 3 image, the gaze 0.25 deg right of the centre: the pixel at
  // (row 1, col 2) has its centre there (x = 0.25, y = 0).
  const Plane w = FovealWeight(4, 3, 0.5, 0.25, 0);
  EXPECT_DOUBLE_EQ(w.at(1, 2), 1.0);
  EXPECT_NEAR(w.at(0, 0), FovealWeightAt(std::hypot(-0.75 - 0.25, 0.5)), 1e-15);
  EXPECT_THROW(FovealWeight(4, 3, 0, 0, 0), Error);
}

TEST(FovealWeight, WeightsEveryMetricsMean) {
  const Image display = Random(180, 180, 6), reference = Random(180, 180, 7);
  Plane uniform{180, 180, std::vector<double>(180 * 180, 2.0)};
  const Plane x = EncodedLuminance(display), y = EncodedLuminance(reference);
  EXPECT_NEAR(Ssim(x, y, 1.0, &uniform), Ssim(x, y, 1.0), 1e-14);
  EXPECT_NEAR(MsSsim(x, y, 1.0, &uniform), MsSsim(x, y, 1.0), 1e-14);
  EXPECT_NEAR(ImagePsnrDb(display, reference, &uniform), ImagePsnrDb(display, reference), 1e-9);
  const Plane a = LuminanceOf(reference, 50), b = LuminanceOf(display, 50);
  EXPECT_NEAR(CsfJnd(a, b, {0.05, 4, &uniform}), CsfJnd(a, b, {0.05, 4, nullptr}), 1e-9);
  // PSNR by hand: two pixels, an error of 0.1 in every channel of the first, weights 3 and 1: the weighted
  // mean square 3 x 3 x 0.01 / (3 x 4) = 0.0075.
  Image one{2, 1, {"R", "G", "B"}, {0.5f, 0.5f, 0.5f, 0.2f, 0.2f, 0.2f}}, other = one;
  for (int c = 0; c < 3; ++c) other.pixels[c] += 0.1f;
  const Plane w{2, 1, {3.0, 1.0}};
  EXPECT_NEAR(ImagePsnrDb(other, one, &w), 10 * std::log10(1 / 0.0075), 1e-5);
  // A difference far from the gaze counts less with the weighting, one at the gaze more.
  const MetricViewing plain{0.05, 50.0}, foveal{0.05, 50.0, true, 0, 0};
  for (bool at_gaze : {false, true}) {
    Image changed = reference;
    const int row0 = at_gaze ? 80 : 0, col0 = at_gaze ? 80 : 0;
    for (int i = row0; i < row0 + 20; ++i)
      for (int j = col0; j < col0 + 20; ++j)
        for (int c = 0; c < 3; ++c) changed.pixels[(size_t(i) * 180 + j) * 3 + c] *= 0.8f;
    for (const char* name : {"psnr", "ssim", "jnd"}) {
      const double weighted = Named(name).score(changed, reference, foveal),
                   unweighted = Named(name).score(changed, reference, plain);
      const bool worse = Named(name).higher_is_better ? weighted < unweighted : weighted > unweighted;
      EXPECT_EQ(worse, at_gaze) << name << (at_gaze ? " at the gaze" : " in the periphery") << ": " << weighted
                                << " against " << unweighted;
    }
  }
  Plane negative = uniform;
  negative.values[5] = -1;
  EXPECT_THROW(Ssim(x, y, 1.0, &negative), Error);
  Plane zero{180, 180, std::vector<double>(180 * 180, 0.0)};
  EXPECT_THROW(CsfJnd(a, b, {0.05, 4, &zero}), Error);
}

}  // namespace
}  // namespace layerlab
