// Stiff and extreme cases for every solver that accepts the display: the
// outputs stay finite, the bounds hold exactly, and the objective ends no
// worse than the initial guess.
#include <cmath>
#include <functional>

#include "layerlab/solvers/solver.h"
#include "layerlab/tests/support/near_first_solver.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

using nlohmann::json;
using testing::ElementNamed;
using testing::ShrunkExample;

struct StiffCase {
  std::string name;
  std::function<json()> scene;
  std::function<void(LightField&)> target;  // edits a mid-gray target
  TargetRange range = TargetRange::kClip;
};

void PrintTo(const StiffCase& c, std::ostream* os) { *os << c.name; }

json Multiplicative() { return ShrunkExample("multiplicative_2layer.json", 24, 12, 3); }
json Hybrid() { return ShrunkExample("paper_prototype.json", 24, 12, 3); }
json Additive() { return ShrunkExample("additive_2layer.json", 24, 12, 3); }

void Keep(LightField&) {}

// The built-ins and one registered here, as a new solver would be.
const SolverRegistry& StiffSolvers() {
  static const SolverRegistry registry = [] {
    SolverRegistry r = SolverRegistry::WithBuiltins();
    r.add(testing::NearFirstSolverType());
    return r;
  }();
  return registry;
}

const StiffCase kCases[] = {
    {"ZeroTargetHybrid", Hybrid, [](LightField& l) { std::fill(l.rgb.begin(), l.rgb.end(), 0.0f); }},
    {"ZeroTargetMultiplicative", Multiplicative, [](LightField& l) { std::fill(l.rgb.begin(), l.rgb.end(), 0.0f); }},
    {"ZeroTargetAdditive", Additive, [](LightField& l) { std::fill(l.rgb.begin(), l.rgb.end(), 0.0f); }},
    {"AllOnesHybrid", Hybrid, [](LightField& l) { std::fill(l.rgb.begin(), l.rgb.end(), 1.0f); }},
    {"AllOnesMultiplicative", Multiplicative, [](LightField& l) { std::fill(l.rgb.begin(), l.rgb.end(), 1.0f); }},
    {"AllOnesAdditive", Additive, [](LightField& l) { std::fill(l.rgb.begin(), l.rgb.end(), 1.0f); }},
    {"OverBrightClipped", Hybrid,
     [](LightField& l) {
       for (float& v : l.rgb) v *= 40.0f;
     }},
    {"OverBrightScaled", Hybrid,
     [](LightField& l) {
       for (float& v : l.rgb) v *= 40.0f;
     },
     TargetRange::kScale},
    {"HdrAdditiveScaled", Additive, [](LightField& l) { l.rgb[17] = 1e4f; }, TargetRange::kScale},
    {"NearlyCoincidentLayers",
     [] {
       json s = Multiplicative();
       ElementNamed(s, "front")["virtual_depth"] = "1.001 D";
       ElementNamed(s, "rear")["virtual_depth"] = "1.0 D";
       return s;
     },
     Keep},
    {"NearlyCoincidentHybridPlanes",
     [] {
       json s = Hybrid();
       ElementNamed(s, "front_a")["virtual_depth"] = "1.0000001 D";
       ElementNamed(s, "rear_a")["virtual_depth"] = "1.0 D";
       ElementNamed(s, "front_b")["virtual_depth"] = "1.0000002 D";
       ElementNamed(s, "rear_b")["virtual_depth"] = "0.9999999 D";
       return s;
     },
     Keep},
    {"LayersFarApart",  // 4.45 D, the spacing the paper questions
     [] {
       json s = Multiplicative();
       ElementNamed(s, "front")["virtual_depth"] = "4.55 D";
       ElementNamed(s, "rear")["virtual_depth"] = "0.1 D";
       return s;
     },
     Keep},
    {"SingleLayer",
     [] {
       json s = Multiplicative();
       ElementNamed(s, "lens")["next"] = "rear";
       s["elements"].erase(2);  // the front panel
       return s;
     },
     Keep},
    {"SingleView",
     [] {
       json s = Hybrid();
       ElementNamed(s, "eye")["views"] = {1, 1};
       return s;
     },
     Keep},
    {"SinglePixel", [] { return ShrunkExample("paper_prototype.json", 1, 1, 2); }, Keep},
    {"LayerAtInfinity",
     [] {
       json s = Multiplicative();
       ElementNamed(s, "rear")["virtual_depth"] = "0 D";
       return s;
     },
     Keep},
};

class StiffCaseTest : public ::testing::TestWithParam<std::tuple<StiffCase, std::string>> {};

TEST_P(StiffCaseTest, StaysFiniteBoundedAndNoWorse) {
  const auto& [c, solver_name] = GetParam();
  DisplaySystem system = testing::CompileJson(c.scene());

  DisplayModel model(system, DisplayLightFieldGeometry(system, 1.3));
  LightField target(model.geometry());
  for (size_t k = 0; k < target.rgb.size(); ++k) target.rgb[k] = 0.2f + 0.6f * float((k * 7919) % 101) / 100.0f;
  c.target(target);

  SolverOptions o = StiffSolvers().get(solver_name).defaults;
  o.iterations = 8;
  o.target_range = c.range;
  Patterns t;
  SolverReport r = StiffSolvers().create(solver_name)->Solve(model, target, o, &t);
  ASSERT_TRUE(r.IsSolutionUsable()) << r.FullReport();
  ASSERT_EQ(t.size(), system.layers.size());
  for (const LayerPattern& p : t)
    for (float v : p.rgb) {
      ASSERT_TRUE(std::isfinite(v));
      ASSERT_GE(v, 0.0f);
      ASSERT_LE(v, 1.0f);
    }
  for (const IterationRecord& it : r.trace) ASSERT_TRUE(std::isfinite(it.objective)) << it.iteration;
  EXPECT_LE(r.final_objective, r.initial_objective * (1 + 1e-9) + 1e-12) << r.FullReport();
  if (c.range == TargetRange::kScale && r.out_of_range) {
    EXPECT_LT(r.target_scale, 1.0);
  }
}

// Every case with every registered solver that accepts its display.
std::vector<std::tuple<StiffCase, std::string>> Applicable() {
  std::vector<std::tuple<StiffCase, std::string>> out;
  for (const StiffCase& c : kCases) {
    DisplaySystem system = testing::CompileJson(c.scene());
    for (const std::string& solver : StiffSolvers().names())
      if (StiffSolvers().get(solver).Unsuitable(system).empty()) out.emplace_back(c, solver);
  }
  return out;
}

INSTANTIATE_TEST_SUITE_P(Stiff, StiffCaseTest, ::testing::ValuesIn(Applicable()), [](const auto& test_info) {
  std::string solver = std::get<1>(test_info.param);
  std::replace(solver.begin(), solver.end(), '-', '_');
  return std::get<0>(test_info.param).name + "_" + solver;
});

}  // namespace
}  // namespace layerlab
