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
              CsfJnd(LuminanceOf(reference, 120.0), LuminanceOf(display, 120.0), {0.05, 4.0}), 1e-12);
  EXPECT_EQ(Named("jnd").higher_is_better, false);
  EXPECT_EQ(Named("psnr").column, "psnr_db");
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
