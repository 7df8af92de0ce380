// Solving through the panels' liquid-crystal response (SolverOptions::lc_response):
// the response map's transpose against the change of the shown patterns it
// maps (the map is linear while no transition turns around); the response
// pass's sums against central differences of the frame's light, summed
// here from ShownOverTime's instants; solvers that model the response show
// the target better than those that assume instant panels; the others
// refuse it.
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <random>

#include "layerlab/framework/lightfield_io.h"
#include "layerlab/kernels/synthesis.h"
#include "layerlab/solvers/objective.h"
#include "layerlab/solvers/response_pass.h"
#include "layerlab/solvers/retinal_objective.h"
#include "layerlab/solvers/solution_writer.h"
#include "layerlab/solvers/solver.h"
#include "layerlab/systems/lc_response.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

// A rank-K stack shrunk to 16 x 8 pixels a layer, its panels rising in `rise` and falling in `fall`.
DisplaySystem Stack(const char* example, const char* rise, const char* fall) {
  nlohmann::json scene = testing::ShrunkExample(example, 16, 8, 3);
  for (nlohmann::json& e : scene["elements"])
    if (e["type"] == "lc_panel") e["rise_time"] = rise, e["fall_time"] = fall;
  return testing::CompileJson(scene);
}

Patterns Random(const DisplayModel& model, unsigned seed, float lo = 0.1f, float hi = 0.95f) {
  return testing::RandomPatterns(model, seed, lo, hi);
}

// The frame's light, each instant synthesized and weighted here.
LightField FrameLight(const DisplayModel& model, const Patterns& t) {
  LightField out(model.geometry());
  for (const ShownInstant& i : ShownOverTime(model.system(), t)) {
    const LightField at = Synthesize(model, i.patterns);
    for (size_t r = 0; r < out.rgb.size(); ++r) out.rgb[r] += static_cast<float>(i.weight * at.rgb[r]);
  }
  return out;
}

double FrameObjective(const DisplayModel& model, const LightField& target, const Patterns& t) {
  const LightField light = FrameLight(model, t);
  double sum = 0;
  for (size_t r = 0; r < light.rgb.size(); ++r) sum += std::pow(double(light.rgb[r]) - target.rgb[r], 2);
  return sum;
}

TEST(ResponseMap, ItsTransposeMapsBackTheChangeItShows) {
  // Fast panels, and slow ones whose start values carry much of the cycle before (prod a_k far from 0).
  for (const auto& [example, rise, fall] :
       std::vector<std::array<const char*, 3>>{{"tensor_display_rank2.json", "3 ms", "9 ms"},
                                               {"tensor_display_rank3.json", "3 ms", "9 ms"},
                                               {"tensor_display_rank2.json", "20 ms", "45 ms"}}) {
    SCOPED_TRACE(std::string(example) + " " + rise + " " + fall);
    const DisplaySystem system = Stack(example, rise, fall);
    ASSERT_TRUE(ResponseMatters(system));
    const DisplayModel model(system, DisplayLightFieldGeometry(system));
    const Patterns t = Random(model, 3);
    Patterns moved = t;
    std::mt19937 rng(4);
    std::uniform_real_distribution<double> u(-1, 1);
    std::vector<std::vector<double>> g(t.size()), delta(t.size());
    for (size_t l = 0; l < t.size(); ++l)
      for (size_t v = 0; v < t[l].rgb.size(); ++v) {
        g[l].push_back(1.5 + u(rng));  // positive, as R's entries are: <R^T g, dt> cannot cancel to 0
        delta[l].push_back(1e-4 * (1.5 + u(rng)));
        moved[l].rgb[v] = static_cast<float>(t[l].rgb[v] + delta[l][v]);
        delta[l][v] = double(moved[l].rgb[v]) - t[l].rgb[v];  // the step the float patterns took
      }
    const ResponseMap at(system, t), at_moved(system, moved);
    ASSERT_EQ(at.instants(), kResponseNodes);
    for (int m = 0; m < at.instants(); ++m) {
      Patterns shown, shown_moved;
      at.Shown(m, &shown);
      at_moved.Shown(m, &shown_moved);
      std::vector<std::vector<double>> back(t.size());
      for (size_t l = 0; l < t.size(); ++l) back[l].assign(t[l].rgb.size(), 0.0);
      at.AddTransposed(m, g, 1.0, nullptr, &back);
      double change = 0, mapped = 0, scale = 0;  // <g, R dt> and <R^T g, dt>
      for (size_t l = 0; l < t.size(); ++l)
        for (size_t v = 0; v < t[l].rgb.size(); ++v) {
          change += g[l][v] * (double(shown_moved[l].rgb[v]) - shown[l].rgb[v]);
          mapped += back[l][v] * delta[l][v];
          scale += std::abs(g[l][v] * delta[l][v]);
        }
      EXPECT_NEAR(change, mapped, 2e-3 * scale) << "node " << m;
      EXPECT_GT(mapped, 0.3 * scale) << "node " << m;
    }
    // A panel's subframes come together: a mask holding one of them is refused.
    std::vector<char> one(t.size(), 0);
    one[0] = 1;
    std::vector<std::vector<double>> back(t.size());
    for (size_t l = 0; l < t.size(); ++l) back[l].assign(t[l].rgb.size(), 0.0);
    EXPECT_THROW(at.AddTransposed(0, g, 1.0, &one, &back), Error);
  }
}

TEST(ResponsePass, IsTheGradientOfTheFramesObjective) {
  const DisplaySystem system = Stack("tensor_display_rank2.json", "4 ms", "8 ms");
  const DisplayModel model(system, DisplayLightFieldGeometry(system));
  const LightField target = Synthesize(model, Random(model, 1));
  const Patterns t = Random(model, 2);
  ResponsePass pass(model, nullptr);
  const double f = pass.Run(target, t);
  EXPECT_NEAR(f, FrameObjective(model, target, t), 1e-5 * f);
  std::mt19937 rng(5);
  for (size_t k = 0; k < t.size(); ++k)
    for (int trial = 0; trial < 6; ++trial) {
      const size_t i = std::uniform_int_distribution<size_t>(0, t[k].rgb.size() - 1)(rng);
      const float h = 2e-3f;
      Patterns plus = t, minus = t;
      plus[k].rgb[i] += h, minus[k].rgb[i] -= h;
      const double difference = (FrameObjective(model, target, plus) - FrameObjective(model, target, minus)) / (2 * h);
      EXPECT_NEAR(2 * pass.residual()[k][i], difference, 2e-3 * std::abs(difference) + 1e-4)
          << "layer " << k << ", value " << i;
      EXPECT_GE(pass.denominator()[k][i], 0);
    }
  // ShownLightField is the frame's light summed here.
  const LightField shown = ShownLightField(model, t);
  const LightField here = FrameLight(model, t);
  for (size_t r = 0; r < shown.rgb.size(); r += 97) EXPECT_NEAR(shown.rgb[r], here.rgb[r], 1e-6);
}

TEST(ResponseSolve, SolvingThroughTheResponseShowsTheTargetBetter) {
  const DisplaySystem system = Stack("tensor_display_rank2.json", "8 ms", "8 ms");
  const DisplayModel model(system, DisplayLightFieldGeometry(system));
  // A target the panels show exactly through their response: some patterns' frame light.
  const LightField target = FrameLight(model, Random(model, 7, 0.2f, 0.9f));
  {
    const SolverType& type = SolverRegistry::Builtins().get("quasi-newton");
    SolverOptions o = type.defaults;
    o.iterations = 150;
    Patterns assuming, through;
    const SolverReport a = type.make()->Solve(model, target, o, &assuming);
    o.lc_response = true;
    const SolverReport b = type.make()->Solve(model, target, o, &through);
    ASSERT_TRUE(a.IsSolutionUsable() && b.IsSolutionUsable()) << b.message;
    EXPECT_FALSE(a.lc_response);
    EXPECT_TRUE(b.lc_response);
    // The trace is the objective of what the panels show.
    const double shown_through = FrameObjective(model, target, through);
    EXPECT_NEAR(b.final_objective, shown_through, 1e-4 * shown_through);
    const double shown_first = FrameObjective(model, target, InitialPatterns(model, o));
    EXPECT_NEAR(b.trace.front().objective, shown_first, 1e-4 * shown_first);
    EXPECT_TRUE(std::isnan(b.shown_psnr_db));  // its PSNR is of what is shown already
    // The light field it writes is the frame's, what it optimized.
    const std::filesystem::path folder =
        std::filesystem::temp_directory_path() / ("layerlab_response_solve_" + std::to_string(::getpid()));
    WriteSolution(model, through, b, folder.string(), {.write_lightfield = true});
    const LightField written = ReadLightField((folder / "lightfield").string());
    const LightField frame = FrameLight(model, through);
    ASSERT_EQ(written.rgb.size(), frame.rgb.size());
    for (size_t r = 0; r < frame.rgb.size(); r += 31) ASSERT_NEAR(written.rgb[r], frame.rgb[r], 1e-6) << r;
    std::filesystem::remove_all(folder);
    const double shown_assuming = FrameObjective(model, target, assuming);
    EXPECT_NEAR(a.shown_psnr_db, PsnrDb(shown_assuming, target.rgb.size()), 1e-3);
    EXPECT_LT(shown_through, 0.33 * shown_assuming);
  }
}

// The retinal objective's pass through the response: its gradient steps lower the retinal objective of the
// frame's light, which the trace records.
TEST(ResponseSolve, TheRetinalObjectiveIsOfTheFramesLight) {
  const DisplaySystem system = Stack("tensor_display_rank2.json", "8 ms", "8 ms");
  const DisplayModel model(system, DisplayLightFieldGeometry(system));
  const LightField target = FrameLight(model, Random(model, 7, 0.2f, 0.9f));
  SolverOptions o = SolverRegistry::Builtins().get("quasi-newton").defaults;
  o.iterations = 20, o.objective = ObjectiveKind::kRetinal, o.lc_response = true;
  Patterns t;
  const SolverReport r = SolverRegistry::Builtins().create("quasi-newton")->Solve(model, target, o, &t);
  ASSERT_TRUE(r.IsSolutionUsable()) << r.message;
  const RetinalObjective objective(model, target, RetinalOptionsOf(o));
  const double f = objective.Evaluate(FrameLight(model, t));
  EXPECT_NEAR(r.final_objective, f, 1e-4 * f);
  EXPECT_LT(r.final_objective, 0.7 * r.trace[2].objective);  // the quasi-Newton steps after the warm start
}

TEST(ResponseSolve, TheHybridRefusesItAndInstantPanelsChangeNothing) {
  const DisplaySystem system = Stack("tensor_display_rank2.json", "8 ms", "8 ms");
  const DisplayModel model(system, DisplayLightFieldGeometry(system));
  const LightField target = Synthesize(model, Random(model, 7));
  for (const char* name : {"hybrid", "multiplicative", "joint"}) {
    SolverOptions o = SolverRegistry::Builtins().get(name).defaults;
    o.lc_response = true;
    Patterns t;
    const SolverReport refused = SolverRegistry::Builtins().create(name)->Solve(model, target, o, &t);
    EXPECT_EQ(refused.termination, Termination::kFailed) << name;
    EXPECT_NE(refused.message.find("\"lc_response\""), std::string::npos) << refused.message;
  }
  const DisplaySystem instant = Stack("tensor_display_rank2.json", "0 ms", "0 ms");
  const DisplayModel instant_model(instant, DisplayLightFieldGeometry(instant));
  SolverOptions m = SolverRegistry::Builtins().get("quasi-newton").defaults;
  m.iterations = 5;
  Patterns plain, asked;
  const SolverReport a = SolverRegistry::Builtins().create("quasi-newton")->Solve(instant_model, target, m, &plain);
  m.lc_response = true;
  const SolverReport b = SolverRegistry::Builtins().create("quasi-newton")->Solve(instant_model, target, m, &asked);
  EXPECT_FALSE(b.lc_response);
  EXPECT_EQ(a.final_objective, b.final_objective);
  for (size_t k = 0; k < plain.size(); ++k) EXPECT_EQ(plain[k].rgb, asked[k].rgb);
}

}  // namespace
}  // namespace layerlab
