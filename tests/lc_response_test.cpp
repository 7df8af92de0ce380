// The liquid crystal's response (systems/lc_response.h): the periodic
// steady state of a pixel's two subframes, rising and falling at their own
// rates, against its closed form solved by hand; the light a two-subframe
// stack shows against the time average of the product of its two relaxing
// panels integrated by hand; instant panels and one subframe show what they
// are driven to; bad times are refused naming the key.
#include <cmath>
#include <functional>

#include "layerlab/kernels/synthesis.h"
#include "layerlab/solvers/objective.h"
#include "layerlab/solvers/solver.h"
#include "layerlab/systems/lc_response.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

TEST(LcResponse, TwoSubframesSettleWhereTheirClosedFormSays) {
  // Rising from s1 to a1 in the first subframe, falling from s2 to a2 in the second:
  //   s2 = a1 + (s1 - a1) e_r,  s1 = a2 + (s2 - a2) e_f
  //   => s1 = (a2 (1 - e_f) + a1 e_f (1 - e_r)) / (1 - e_r e_f).
  const double a1 = 0.8, a2 = 0.2, T = 1 / 120.0, rise = 2e-3, fall = 6e-3;
  const double er = std::exp(-T * kTenToNinetyPerTau / rise), ef = std::exp(-T * kTenToNinetyPerTau / fall);
  const double s1 = (a2 * (1 - ef) + a1 * ef * (1 - er)) / (1 - er * ef), s2 = a1 + (s1 - a1) * er;
  const std::vector<double> start = SteadyStartValues({a1, a2}, T, rise, fall);
  ASSERT_EQ(start.size(), 2u);
  EXPECT_NEAR(start[0], s1, 1e-14);
  EXPECT_NEAR(start[1], s2, 1e-14);
  // 10 to 90 % in rise_time: from 0 to 1, after rise_time the value is 0.9 of the way from the 0.1 point's time.
  EXPECT_NEAR(std::log(9.0), kTenToNinetyPerTau, 1e-15);
  // Instant panels hold their driven values.
  EXPECT_EQ(SteadyStartValues({a1, a2}, T, 0, 0), (std::vector<double>{a2, a1}));
}

DisplaySystem RankTwo(const std::string& rise, const std::string& fall) {
  nlohmann::json scene = testing::ShrunkExample("tensor_display_rank2.json", 16, 8, 3);
  for (nlohmann::json& e : scene["elements"])
    if (e["type"] == "lc_panel") e["rise_time"] = rise, e["fall_time"] = fall;
  return testing::CompileJson(scene);
}

TEST(LcResponse, AStacksLightIsTheTimeAverageOfItsRelaxingPanels) {
  const double tau_time = 4e-3;
  const DisplaySystem system = RankTwo("4 ms", "4 ms");
  ASSERT_TRUE(ResponseMatters(system));
  const DisplayModel model(system, DisplayLightFieldGeometry(system));
  // Uniform patterns: front a_k, rear b_k in subframe k.
  const double a[2] = {0.9, 0.3}, b[2] = {0.4, 0.7};
  Patterns driven = model.UniformPatterns(0.f);
  for (size_t l = 0; l < system.layers.size(); ++l) {
    const VirtualLayer& layer = system.layers[l];
    const double v = layer.element == "front" ? a[layer.subframe] : b[layer.subframe];
    for (float& x : driven[l].rgb) x = static_cast<float>(v);
  }
  LightField shown(model.geometry());
  for (const ShownInstant& i : ShownOverTime(system, driven)) {
    const LightField at = Synthesize(model, i.patterns);
    for (size_t r = 0; r < shown.rgb.size(); ++r) shown.rgb[r] += static_cast<float>(i.weight * at.rgb[r]);
  }
  // By hand: each subframe k's weight W_k (its light with both panels at 1, the other subframe dark), and
  //   (1/T) int_0^T (a + da e^{-s/tau})(b + db e^{-s/tau}) ds
  //     = ab + (a db + b da) (tau/T)(1 - e) + da db (tau/(2T))(1 - e^2),  e = exp(-T/tau).
  const double T = 1 / (2 * system.frame_rate_hz), tau = tau_time / kTenToNinetyPerTau, e = std::exp(-T / tau);
  auto start = [&](const double* v, int k) { return (v[1 - k] + v[k] * e) / (1 + e); };  // closed form, 2 subframes
  std::vector<LightField> unit;
  for (int k = 0; k < 2; ++k) {
    Patterns p = model.UniformPatterns(0.f);
    for (size_t l = 0; l < system.layers.size(); ++l)
      if (system.layers[l].subframe == k) std::fill(p[l].rgb.begin(), p[l].rgb.end(), 1.0f);
    unit.push_back(Synthesize(model, p));
  }
  const size_t ray = shown.rgb.size() / 2 / 3 * 3 + 1;  // a middle ray's green
  double expected = 0;
  for (int k = 0; k < 2; ++k) {
    const double da = start(a, k) - a[k], db = start(b, k) - b[k];
    expected += unit[k].rgb[ray] *
                (a[k] * b[k] + (a[k] * db + b[k] * da) * (tau / T) * (1 - e) + da * db * (tau / (2 * T)) * (1 - e * e));
  }
  ASSERT_GT(unit[0].rgb[ray], 0.f);
  EXPECT_NEAR(shown.rgb[ray], expected, 1e-6 * expected);
  // And it differs from the instant panels' light by more than that.
  const double instant = unit[0].rgb[ray] * a[0] * b[0] + unit[1].rgb[ray] * a[1] * b[1];
  EXPECT_GT(std::abs(expected - instant), 0.05 * instant);
}

TEST(LcResponse, InstantPanelsOrOneSubframeShowWhatTheyAreDriven) {
  const DisplaySystem instant = RankTwo("0 ms", "0 ms");
  EXPECT_FALSE(ResponseMatters(instant));
  const DisplayModel model(instant, DisplayLightFieldGeometry(instant));
  const Patterns driven = model.UniformPatterns(0.4f);
  const std::vector<ShownInstant> shown = ShownOverTime(instant, driven);
  ASSERT_EQ(shown.size(), 1u);
  EXPECT_EQ(shown[0].weight, 1.0);
  nlohmann::json scene = testing::ShrunkExample("multiplicative_2layer.json", 16, 8, 3);
  for (nlohmann::json& e : scene["elements"])
    if (e["type"] == "lc_panel") e["rise_time"] = "8 ms";
  EXPECT_FALSE(ResponseMatters(testing::CompileJson(scene)));  // one subframe: the steady state is the driven value
}

// The solve assumes instant panels; its report adds the PSNR of what its patterns show through the response.
TEST(LcResponse, ASolvesReportSaysWhatItsPanelsShow) {
  for (const char* time : {"0 ms", "4 ms"}) {
    const DisplaySystem system = RankTwo(time, time);
    const DisplayModel model(system, DisplayLightFieldGeometry(system));
    Patterns truth = model.UniformPatterns(0.3f);
    for (size_t l = 0; l < truth.size(); ++l)
      for (size_t v = 0; v < truth[l].rgb.size(); ++v) truth[l].rgb[v] = 0.2f + 0.6f * float((v * 7 + l * 3) % 11) / 10;
    const LightField target = Synthesize(model, truth);
    SolverOptions o = SolverRegistry::Builtins().get("multiplicative").defaults;
    o.iterations = 5;
    Patterns t;
    const SolverReport r = SolverRegistry::Builtins().create("multiplicative")->Solve(model, target, o, &t);
    if (!ResponseMatters(system)) {
      EXPECT_TRUE(std::isnan(r.shown_psnr_db));
      continue;
    }
    LightField shown(model.geometry());
    for (const ShownInstant& i : ShownOverTime(system, t)) {
      const LightField at = Synthesize(model, i.patterns);
      for (size_t k = 0; k < shown.rgb.size(); ++k) shown.rgb[k] += static_cast<float>(i.weight * at.rgb[k]);
    }
    double error = 0;
    for (size_t k = 0; k < shown.rgb.size(); ++k) error += std::pow(double(shown.rgb[k]) - target.rgb[k], 2);
    EXPECT_NEAR(r.shown_psnr_db, PsnrDb(error, shown.rgb.size()), 1e-6);
    EXPECT_LT(r.shown_psnr_db, r.final_psnr_db);
  }
}

// Negative times, rates and luminances, each refused naming its JSON pointer.
TEST(LcResponse, NegativeTimesRatesAndLuminancesAreRefusedNamingTheKey) {
  auto refused = [](const std::function<void(nlohmann::json&)>& edit, const std::string& pointer) {
    nlohmann::json scene = testing::ShrunkExample("tensor_display_rank2.json", 16, 8, 3);
    edit(scene);
    try {
      testing::CompileJson(scene);
      ADD_FAILURE() << pointer << " accepted";
    } catch (const Error& error) {
      EXPECT_NE(std::string(error.what()).find(pointer), std::string::npos) << error.what();
    }
  };
  for (const char* key : {"rise_time", "fall_time"})
    refused(
        [&](nlohmann::json& scene) {
          for (nlohmann::json& e : scene["elements"])
            if (e["type"] == "lc_panel") e[key] = "-1 ms";
        },
        key);
  refused([](nlohmann::json& scene) { scene["frame_rate"] = "-60 Hz"; }, "/frame_rate");
  refused([](nlohmann::json& scene) { scene["frame_rate"] = 0; }, "/frame_rate");
  refused(
      [](nlohmann::json& scene) {
        for (nlohmann::json& e : scene["elements"])
          if (e["type"] == "backlight") e["luminance"] = "-250 cd/m2";
      },
      "/luminance");
}

}  // namespace
}  // namespace layerlab
