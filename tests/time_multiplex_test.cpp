// Time-multiplexed displays against independent constructions: a K-subframe
// display's light field is the mean of K single-subframe displays built on
// their own; a multifocal display (one panel behind a tunable lens) is the
// mean of K single-plane displays at the depths worked out from the powers;
// a known rank-K target is recovered; "subframes": 1 is today's display.
#include <cmath>
#include <map>

#include "framework/random.h"
#include "solvers/solver.h"
#include "tests/test_util.h"

namespace layerlab {
namespace {

using nlohmann::json;
using testing::Close;
using testing::CompileJson;
using testing::ElementNamed;
using testing::ShrunkExample;

Patterns RandomPatterns(const DisplayModel& model, uint64_t seed) {
  Patterns t = model.UniformPatterns(0.5f);
  SplitMix64 random(seed);
  for (LayerPattern& p : t)
    for (float& v : p.rgb) v = static_cast<float>(0.1 + 0.9 * random.uniform());
  return t;
}

const LayerPattern& PatternOf(const DisplaySystem& s, const Patterns& t, const std::string& element, int subframe) {
  for (size_t k = 0; k < s.layers.size(); ++k)
    if (s.layers[k].element == element && s.layers[k].subframe == subframe) return t[k];
  throw std::runtime_error("no layer " + element);
}

double MaxDifference(const LightField& a, const LightField& b) {
  double worst = 0;
  for (size_t i = 0; i < a.rgb.size(); ++i) worst = std::max(worst, double(std::abs(a.rgb[i] - b.rgb[i])));
  return worst;
}

TEST(TimeMultiplex, SubframesAreSeenAsTheirMean) {
  const json scene = ShrunkExample("tensor_display_rank3.json", 32, 16, 5);
  const DisplaySystem system = CompileJson(scene);
  ASSERT_EQ(system.subframes, 3);
  ASSERT_EQ(system.layers.size(), 6u);
  ASSERT_EQ(system.branches.size(), 3u);
  const LightFieldGeometry geometry = DisplayLightFieldGeometry(system);
  const DisplayModel model(system, geometry);
  const Patterns t = RandomPatterns(model, 3);
  const LightField mixed = model.Synthesize(t);

  // Each subframe on its own: the same display without time multiplexing.
  json single = scene;
  single.erase("subframes");
  const DisplaySystem one = CompileJson(single);
  const DisplayModel one_model(one, geometry);
  LightField mean(geometry);
  for (int k = 0; k < 3; ++k) {
    Patterns tk;
    for (const VirtualLayer& l : one.layers) tk.push_back(PatternOf(system, t, l.element, k));
    const LightField lk = one_model.Synthesize(tk);
    for (size_t i = 0; i < mean.rgb.size(); ++i) mean.rgb[i] += lk.rgb[i] / 3.0f;
  }
  EXPECT_LT(MaxDifference(mixed, mean), 2e-6);
  // Brightness: full white in every subframe is the single display's white.
  EXPECT_TRUE(Close(system.peak_luminance[1], one.peak_luminance[1], 1e-12));
  EXPECT_TRUE(Close(system.luminance_efficiency, one.luminance_efficiency, 1e-12));
}

TEST(TimeMultiplex, MultifocalIsTheMeanOfSinglePlaneDisplays) {
  const json scene = ShrunkExample("multifocal_tunable_4plane.json", 32, 16, 5);
  const DisplaySystem system = CompileJson(scene);
  ASSERT_EQ(system.layers.size(), 4u);
  const std::vector<std::string> powers = scene["elements"][1]["powers"];
  const double e = 0.01, s = 0.07;
  const LightFieldGeometry geometry = DisplayLightFieldGeometry(system);
  const DisplayModel model(system, geometry);
  const Patterns t = RandomPatterns(model, 5);
  const LightField mixed = model.Synthesize(t);
  LightField mean(geometry);
  for (int k = 0; k < 4; ++k) {
    // Eq. 1 with f = 1/P: the panel s behind the lens is imaged at D = (1 - s P) / (e + s (1 - e P)).
    const double P = std::stod(powers[k]);
    const double D = (1 - s * P) / (e + s * (1 - e * P));
    const VirtualLayer& l = system.layers[k];  // farthest first, as the powers go
    EXPECT_TRUE(Close(l.diopters, D, 1e-12)) << k;
    EXPECT_EQ(l.subframe, k);
    // The single-plane display: a thin lens of that power, the same panel.
    json plane = scene;
    plane.erase("subframes");
    json& lens = ElementNamed(plane, "tunable");
    lens = {{"type", "thin_lens"}, {"name", "tunable"}, {"focal_length", 1.0 / P}, {"next", "panel"}};
    const DisplaySystem one = CompileJson(plane);
    EXPECT_TRUE(Close(one.layers[0].diopters, D, 1e-12));
    const LightField lk = DisplayModel(one, geometry).Synthesize({PatternOf(system, t, "panel", k)});
    for (size_t i = 0; i < mean.rgb.size(); ++i) mean.rgb[i] += lk.rgb[i] / 4.0f;
  }
  EXPECT_LT(MaxDifference(mixed, mean), 2e-6);
}

// Smooth patterns in [0.2, 0.9]: sums of low-frequency cosines, different in each layer.
Patterns SmoothPatterns(const DisplayModel& model, uint64_t seed) {
  Patterns t = model.UniformPatterns(0.5f);
  SplitMix64 random(seed);
  for (LayerPattern& p : t)
    for (int c = 0; c < 3; ++c) {
      const double fx = 0.5 + 2.5 * random.uniform(), fy = 0.5 + 2.5 * random.uniform(), ph = 6.283 * random.uniform();
      for (int i = 0; i < p.rows; ++i)
        for (int j = 0; j < p.cols; ++j)
          p.rgb[(size_t(i) * p.cols + j) * 3 + c] =
              float(0.55 + 0.35 * std::cos(6.283 * (fx * j / p.cols + fy * i / p.rows) + ph));
    }
  return t;
}

// The subframes of one stack trade patterns among themselves without changing
// the mean (a continuous family of exact solutions), which slows the last
// digits: 800 iterations reach about 53 dB (docs/time-multiplexing.md).
TEST(TimeMultiplex, KnownRankThreeTargetIsApproached) {
  const DisplaySystem system = CompileJson(ShrunkExample("tensor_display_rank3.json", 32, 16, 7));
  const DisplayModel model(system, DisplayLightFieldGeometry(system));
  const LightField target = model.Synthesize(SmoothPatterns(model, 9));
  for (const char* solver : {"quasi-newton"}) {
    SolverOptions o = SolverRegistry::Builtins().find(solver)->defaults;
    o.iterations = 800;
    o.tolerance = 0;
    Patterns t;
    SolverReport r = SolverRegistry::Builtins().create(solver)->Solve(model, target, o, &t);
    ASSERT_TRUE(r.IsSolutionUsable()) << r.FullReport();
    EXPECT_GT(r.final_psnr_db, 50.0) << solver << "\n" << r.BriefReport();
  }
}

TEST(TimeMultiplex, OneSubframeIsTodaysDisplay) {
  json scene = ShrunkExample("multiplicative_2layer.json", 24, 12, 3);
  const DisplaySystem today = CompileJson(scene);
  scene["subframes"] = 1;
  const DisplaySystem one = CompileJson(scene);
  const DisplayModel a(today, DisplayLightFieldGeometry(today)), b(one, DisplayLightFieldGeometry(one));
  const LightField target = a.Synthesize(RandomPatterns(a, 1));
  for (const char* solver : {"multiplicative", "joint", "quasi-newton", "hybrid"}) {
    SolverOptions o = SolverRegistry::Builtins().find(solver)->defaults;
    o.iterations = 5;
    Patterns ta, tb;
    SolverRegistry::Builtins().create(solver)->Solve(a, target, o, &ta);
    SolverRegistry::Builtins().create(solver)->Solve(b, target, o, &tb);
    ASSERT_EQ(ta.size(), tb.size());
    for (size_t k = 0; k < ta.size(); ++k) EXPECT_EQ(ta[k].rgb, tb[k].rgb) << solver;
  }
  for (size_t k = 0; k < today.layers.size(); ++k) EXPECT_EQ(today.layers[k].name, one.layers[k].name);
}

TEST(TimeMultiplex, MalformedSubframesAreRefused) {
  json scene = testing::ReadExample("multifocal_tunable_4plane.json");
  json zero = scene;
  zero["subframes"] = 0;
  EXPECT_EQ(testing::CompileError(zero), "scene.json: /subframes: expected an integer in [1, 64], got 0");

  json three = scene;
  three["subframes"] = 3;
  EXPECT_EQ(testing::CompileError(three),
            "scene.json: /elements/1: \"tunable\" gives 4 powers, one per subframe, but the scene shows 3 "
            "(\"subframes\": 3 at the top of the scene) (in subframe 1 of 3)");

  json behind = scene;
  behind["elements"][1]["powers"][2] = "30 D";  // the panel 70 mm behind a 33 mm lens: a real image behind the eye
  EXPECT_NE(testing::CompileError(behind).find("beyond the focal length 33.33 mm: the lens would form a real, inverted "
                                               "image"),
            std::string::npos)
      << testing::CompileError(behind);
  EXPECT_NE(testing::CompileError(behind).find("(in subframe 3 of 4)"), std::string::npos);

  json moving = scene;
  ElementNamed(moving, "panel").erase("distance");
  ElementNamed(moving, "panel")["virtual_depth"] = "1 D";
  EXPECT_EQ(testing::CompileError(moving),
            "scene.json: /elements/2/virtual_depth: \"virtual_depth\" places a panel where its image should be, but "
            "behind the tunable \"tunable\" the image moves from subframe to subframe; place \"panel\" by \"distance\" "
            "or \"gap\" (in subframe 1 of 4)");

  json no_powers = scene;
  no_powers["elements"][1].erase("powers");
  EXPECT_EQ(testing::CompileError(no_powers),
            "scene.json: /elements/1/powers: missing key: give \"powers\" (one optical power per subframe, e.g. "
            "[\"13.9 D\", \"12.0 D\"]) or \"focal_lengths\"");
}

}  // namespace
}  // namespace layerlab
