// The flicker check of a time-multiplexed display (analysis/flicker_check.h)
// against the Fourier series of its luminance worked out here: with instant
// panels a two-subframe square wave of contrast C has a fundamental of
// modulation (4 / pi) C and no second harmonic; through an 8 ms response the
// product of the two panels' relaxing transmittances, integrated over the
// frame by a fine midpoint rule here, gives the fundamental's modulation;
// the visibility is that modulation times the eye's sensitivity at the
// region's luminance, area and eccentricity; a display of one subframe has
// no verdict; `info`'s worst case against its own square wave.
#include <cmath>
#include <complex>
#include <numbers>

#include "layerlab/analysis/flicker_check.h"
#include "layerlab/eye/temporal_csf.h"
#include "layerlab/systems/lc_response.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

DisplaySystem RankTwo(const char* time) {
  nlohmann::json scene = testing::ShrunkExample("tensor_display_rank2.json", 16, 8, 3);
  for (nlohmann::json& e : scene["elements"])
    if (e["type"] == "lc_panel") e["rise_time"] = time, e["fall_time"] = time;
  return testing::CompileJson(scene);
}

// Uniform patterns: front a[k], rear b[k] in subframe k.
Patterns Uniform(const DisplaySystem& system, const DisplayModel& model, const double a[2], const double b[2]) {
  Patterns t = model.UniformPatterns(0.f);
  for (size_t l = 0; l < system.layers.size(); ++l) {
    const VirtualLayer& layer = system.layers[l];
    const double v = layer.element == "front" ? a[layer.subframe] : b[layer.subframe];
    for (float& x : t[l].rgb) x = static_cast<float>(v);
  }
  return t;
}

void ExpectVisibilityIsModulationTimesSensitivity(const FlickerVerdict& f) {
  const FlickerConditions at{f.luminance_cd_m2, f.region_w_deg * f.region_h_deg, std::hypot(f.x_deg, f.y_deg)};
  EXPECT_NEAR(f.visibility, f.modulation * TemporalContrastSensitivity(f.frequency_hz, at), 1e-9 * f.visibility);
  EXPECT_EQ(f.visible(), f.visibility > 1);
}

TEST(FlickerCheck, InstantPanelsShowASquareWave) {
  const DisplaySystem system = RankTwo("0 ms");
  const DisplayModel model(system, DisplayLightFieldGeometry(system));
  const double a[2] = {0.9, 0.3}, b[2] = {0.8, 0.5};
  const std::optional<FlickerVerdict> f = CheckFlicker(model, Uniform(system, model, a, b));
  ASSERT_TRUE(f);
  const double on = a[0] * b[0], off = a[1] * b[1], contrast = (on - off) / (on + off);
  EXPECT_NEAR(f->modulation, 4 / std::numbers::pi * contrast, 1e-4);
  EXPECT_DOUBLE_EQ(f->frequency_hz, system.frame_rate_hz);  // the fundamental; a square wave has no 2nd harmonic
  ExpectVisibilityIsModulationTimesSensitivity(*f);
  // The same content in both subframes is steady.
  const double same[2] = {0.6, 0.6};
  EXPECT_NEAR(CheckFlicker(model, Uniform(system, model, same, same))->modulation, 0, 1e-5);
}

TEST(FlickerCheck, ThroughTheResponseTheFundamentalIsTheRelaxingProducts) {
  const DisplaySystem system = RankTwo("8 ms");
  const DisplayModel model(system, DisplayLightFieldGeometry(system));
  const double a[2] = {0.9, 0.3}, b[2] = {0.8, 0.5};
  const std::optional<FlickerVerdict> f = CheckFlicker(model, Uniform(system, model, a, b));
  ASSERT_TRUE(f);
  // By hand: each panel relaxes as x(s) = v_k + (x0_k - v_k) e^{-s/tau}, x0_k = (v_{1-k} + v_k e) / (1 + e), e = e^{-T/tau}.
  const double T = 1 / (2 * system.frame_rate_hz), tau = 8e-3 / kTenToNinetyPerTau, e = std::exp(-T / tau);
  auto x = [&](const double* v, int k, double s) {
    const double x0 = (v[1 - k] + v[k] * e) / (1 + e);
    return v[k] + (x0 - v[k]) * std::exp(-s / tau);
  };
  std::complex<double> c0 = 0, c1 = 0;
  const int steps = 20000;
  for (int k = 0; k < 2; ++k)
    for (int i = 0; i < steps; ++i) {
      const double s = (i + 0.5) * T / steps, t = k * T + s;
      const double light = x(a, k, s) * x(b, k, s) / (2.0 * steps);
      c0 += light;
      c1 += light * std::exp(std::complex<double>(0, -2 * std::numbers::pi * t / (2 * T)));
    }
  EXPECT_NEAR(f->modulation, 2 * std::abs(c1) / std::abs(c0), 1e-4);
  const double on = a[0] * b[0], off = a[1] * b[1];
  EXPECT_LT(f->modulation, 0.9 * 4 / std::numbers::pi * (on - off) / (on + off));  // the response smooths it
  ExpectVisibilityIsModulationTimesSensitivity(*f);
}

TEST(FlickerCheck, OneSubframeIsSteadyAndInfosWorstCaseIsAPulse) {
  nlohmann::json scene = testing::ShrunkExample("multiplicative_2layer.json", 16, 8, 3);
  const DisplaySystem one = testing::CompileJson(scene);
  const DisplayModel model(one, DisplayLightFieldGeometry(one));
  EXPECT_FALSE(CheckFlicker(model, model.UniformPatterns(0.5f)));
  EXPECT_FALSE(WorstCaseFlicker(one));
  // Rank 2, instant: a pulse in one of two subframes is a square wave of contrast 1.
  const std::optional<FlickerVerdict> worst = WorstCaseFlicker(RankTwo("0 ms"));
  ASSERT_TRUE(worst);
  EXPECT_NEAR(worst->modulation, 4 / std::numbers::pi, 1e-9);
  ExpectVisibilityIsModulationTimesSensitivity(*worst);
}

}  // namespace
}  // namespace layerlab
