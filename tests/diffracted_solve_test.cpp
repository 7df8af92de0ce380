// Solving through the panels' diffraction (SolverOptions::panel_diffraction):
// the joint pass's sums are the gradient of the objective of the diffracted
// patterns D t (central differences of Objective(D t), computed here), and
// the solvers that model it reach a lower objective as the eye sees the
// display than a solve that ignores it; the others refuse it.
#include <cmath>
#include <random>

#include "layerlab/kernels/joint_pass.h"
#include "layerlab/kernels/synthesis.h"
#include "layerlab/solvers/objective.h"
#include "layerlab/solvers/solver.h"
#include "layerlab/systems/panel_diffraction.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

// An example shrunk to 24 x 12 pixels a layer, its panels' black matrix `fill`: by default the
// multiplicative baseline (one stack); the paper's prototype has two, each diffracting its rear layer.
DisplaySystem Stack(double fill, const std::string& example = "multiplicative_2layer.json") {
  nlohmann::json scene = testing::ShrunkExample(example, 24, 12, 5);
  for (nlohmann::json& e : scene["elements"])
    if (e["type"] == "lc_panel") e["fill_factor"] = fill;
  return testing::CompileJson(scene);
}

Patterns Random(const DisplayModel& model, unsigned seed) {
  Patterns t = model.UniformPatterns(0.5f);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.2f, 0.9f);
  for (LayerPattern& p : t)
    for (float& v : p.rgb) v = u(rng);
  return t;
}

class DiffractedPass : public ::testing::TestWithParam<std::string> {};

TEST_P(DiffractedPass, IsTheGradientOfTheDiffractedObjective) {
  const DisplaySystem system = Stack(0.5, GetParam());
  const std::vector<LayerDiffraction> d = PanelDiffraction(system);
  ASSERT_EQ(d.size(), system.branches.size());
  ASSERT_LT(d[0].axes[1][0].weight[d[0].axes[1][0].reach], 0.9);  // a kernel far from the identity
  DisplaySystem rotated = system;                                 // the general (ray by ray) path
  for (VirtualLayer& layer : rotated.layers) layer.rotation_rad = 1e-12;
  const DisplayModel fast(system, DisplayLightFieldGeometry(system)), general(rotated, fast.geometry());
  const LightField target = Synthesize(fast, Random(fast, 1));
  const Patterns t = Random(fast, 2);
  auto objective = [&](const DisplayModel& model, const Patterns& p) {
    return Objective(model, target, DiffractedPatterns(d, p));
  };
  for (const DisplayModel* model : {&fast, &general}) {
    JointPass pass(*model, nullptr, &d);
    const double f = pass.Run(target, t);
    EXPECT_NEAR(f, objective(*model, t), 1e-6 * f);
    std::mt19937 rng(5);
    for (size_t k = 0; k < t.size(); ++k)
      for (int trial = 0; trial < 8; ++trial) {
        const size_t i = std::uniform_int_distribution<size_t>(0, t[k].rgb.size() - 1)(rng);
        const float h = 1e-2f;
        Patterns plus = t, minus = t;
        plus[k].rgb[i] += h, minus[k].rgb[i] -= h;
        // Quadratic in one value: central differences are exact up to round-off.
        const double difference = (objective(*model, plus) - objective(*model, minus)) / (2 * h);
        EXPECT_NEAR(2 * pass.residual()[k][i], difference, 1e-3 * std::abs(difference) + 1e-4)
            << "layer " << k << ", value " << i;
        EXPECT_GE(pass.denominator()[k][i], 0);
      }
  }
}

INSTANTIATE_TEST_SUITE_P(DiffractedSolve, DiffractedPass,
                         ::testing::Values("multiplicative_2layer.json", "paper_prototype.json"),
                         [](const ::testing::TestParamInfo<std::string>& i) {
                           return i.param == "paper_prototype.json" ? "TwoStacks" : "OneStack";
                         });

TEST(DiffractedSolve, SolvingThroughTheGridBeatsIgnoringIt) {
  const DisplaySystem system = Stack(0.5);
  const std::vector<LayerDiffraction> d = PanelDiffraction(system);
  const DisplayModel model(system, DisplayLightFieldGeometry(system));
  // A target the display shows exactly as the eye sees it: its patterns' light through the grid.
  const LightField target = Synthesize(model, DiffractedPatterns(d, Random(model, 7)));
  for (const char* name : {"multiplicative", "joint", "quasi-newton"}) {
    SCOPED_TRACE(name);
    const SolverType& type = SolverRegistry::Builtins().get(name);
    SolverOptions o = type.defaults;
    o.iterations = 60;
    Patterns ignoring, through;
    const SolverReport a = type.make()->Solve(model, target, o, &ignoring);
    o.panel_diffraction = true;
    const SolverReport b = type.make()->Solve(model, target, o, &through);
    ASSERT_TRUE(a.IsSolutionUsable() && b.IsSolutionUsable()) << b.message;
    EXPECT_FALSE(a.panel_diffraction);
    EXPECT_TRUE(b.panel_diffraction);
    // The trace is the objective as the eye sees the display.
    const double seen_through = Objective(model, target, DiffractedPatterns(d, through));
    EXPECT_NEAR(b.final_objective, seen_through, 1e-5 * seen_through);
    const double seen_first = Objective(model, target, DiffractedPatterns(d, InitialPatterns(model, o)));
    EXPECT_NEAR(b.trace.front().objective, seen_first, 1e-5 * seen_first);
    const double seen_ignoring = Objective(model, target, DiffractedPatterns(d, ignoring));
    EXPECT_LT(seen_through, 0.5 * seen_ignoring);
    if (std::string(name) == "multiplicative") {  // Lee-Seung's steps never raise it
      for (size_t k = 1; k < b.trace.size(); ++k)
        EXPECT_LE(b.trace[k].objective, b.trace[k - 1].objective * (1 + 1e-6)) << "iteration " << k;
    }
  }
}

TEST(DiffractedSolve, TheHybridRefusesItAndNothingChangesWhereNoPanelDiffracts) {
  const DisplaySystem system = Stack(0.5);
  const DisplayModel model(system, DisplayLightFieldGeometry(system));
  const LightField target = Synthesize(model, Random(model, 7));
  SolverOptions o = SolverRegistry::Builtins().get("hybrid").defaults;
  o.panel_diffraction = true;
  Patterns t;
  const SolverReport refused = SolverRegistry::Builtins().create("hybrid")->Solve(model, target, o, &t);
  EXPECT_EQ(refused.termination, Termination::kFailed);
  EXPECT_NE(refused.message.find("\"panel_diffraction\""), std::string::npos) << refused.message;
  // Without a black matrix the option is no change at all.
  const DisplaySystem clear = Stack(1.0);
  const DisplayModel clear_model(clear, DisplayLightFieldGeometry(clear));
  SolverOptions m = SolverRegistry::Builtins().get("multiplicative").defaults;
  m.iterations = 5;
  Patterns plain, asked;
  const SolverReport a = SolverRegistry::Builtins().create("multiplicative")->Solve(clear_model, target, m, &plain);
  m.panel_diffraction = true;
  const SolverReport b = SolverRegistry::Builtins().create("multiplicative")->Solve(clear_model, target, m, &asked);
  EXPECT_FALSE(b.panel_diffraction);
  EXPECT_EQ(a.final_objective, b.final_objective);
  for (size_t k = 0; k < plain.size(); ++k) EXPECT_EQ(plain[k].rgb, asked[k].rgb);
}

}  // namespace
}  // namespace layerlab
