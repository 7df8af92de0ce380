// Solvers describe themselves: which displays they suit, which one a display
// gets by default, what they hold in memory and which "solve" keys they
// read; a solver registered here, as a new one would be, is run by
// `compare` like the built-ins.
#include <algorithm>
#include <cmath>

#include "layerlab/kernels/synthesis.h"
#include "layerlab/layerlab.h"  // the data-flow header: the phases used here all come through it
#include "layerlab/tests/support/near_first_solver.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

using nlohmann::json;
using testing::CompileJson;
using testing::ShrunkExample;

SolverRegistry WithNearFirst() {
  SolverRegistry r = SolverRegistry::WithBuiltins();
  r.add(testing::NearFirstSolverType());
  return r;
}

TEST(SolverRegistry, DefaultsFollowTheDisplaysStructure) {
  // The rule, by hand: one branch -> multiplicative; one layer per branch ->
  // additive-trust-region; else hybrid.
  const std::pair<const char*, const char*> expected[] = {{"multiplicative_2layer.json", "multiplicative"},
                                                          {"additive_2layer.json", "additive-trust-region"},
                                                          {"paper_prototype.json", "hybrid"},
                                                          {"hybrid_pbs_hwp.json", "hybrid"}};
  for (const auto& [example, solver] : expected) {
    const DisplaySystem system = CompileJson(ShrunkExample(example, 8, 4, 2));
    EXPECT_EQ(SolverRegistry::Builtins().DefaultFor(system), solver) << example;
    EXPECT_EQ(DefaultSolverFor(system), solver) << example;
    EXPECT_EQ(UnsuitableSolver(solver, system), "") << example;
  }
  // A registered solver of higher rank becomes the default where it suits.
  SolverRegistry r = SolverRegistry::WithBuiltins();
  SolverType preferred = testing::NearFirstSolverType();
  preferred.default_rank = 10;
  r.add(preferred);
  EXPECT_EQ(r.DefaultFor(CompileJson(ShrunkExample("multiplicative_2layer.json", 8, 4, 2))), "near-first");
  EXPECT_EQ(r.DefaultFor(CompileJson(ShrunkExample("paper_prototype.json", 8, 4, 2))), "hybrid");
}

TEST(SolverRegistry, UnsuitableSolversSayWhy) {
  const DisplaySystem paper = CompileJson(ShrunkExample("paper_prototype.json", 8, 4, 2));
  EXPECT_EQ(UnsuitableSolver("multiplicative", paper), "needs a display of one branch; this one has 2 (use hybrid)");
  EXPECT_EQ(UnsuitableSolver("additive-trust-region", paper),
            "needs one layer per branch; branch \"half_mirror.transmitted\" stacks 2 (use hybrid)");
  EXPECT_EQ(UnsuitableSolver("joint", paper), "");
  try {
    UnsuitableSolver("hybird", paper);
    FAIL() << "an unknown solver was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(
        std::string(e.what()),
        "unknown solver \"hybird\"; did you mean \"hybrid\"? Known solvers: additive-trust-region, hybrid, joint, "
        "multiplicative, quasi-newton");
  }
}

TEST(SolverRegistry, RefusesNamesTwiceAndTypesWithoutFactory) {
  SolverRegistry r = WithNearFirst();
  try {
    r.add(testing::NearFirstSolverType());
    FAIL() << "registered twice";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), "solver \"near-first\" is registered twice");
  }
  try {
    SolverType empty;
    empty.name = "empty";
    r.add(empty);
    FAIL() << "registered without a factory";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), "solver \"empty\" has no factory");
  }
}

TEST(SolverRegistry, EveryBuiltinDescribesItself) {
  const DisplaySystem examples[] = {CompileJson(ShrunkExample("multiplicative_2layer.json", 8, 4, 2)),
                                    CompileJson(ShrunkExample("additive_2layer.json", 8, 4, 2)),
                                    CompileJson(ShrunkExample("paper_prototype.json", 8, 4, 2))};
  for (const std::string& name : SolverRegistry::Builtins().names()) {
    const SolverType& type = SolverRegistry::Builtins().get(name);
    EXPECT_FALSE(type.summary.empty()) << name;
    std::string error;
    EXPECT_TRUE(type.defaults.IsValid(&error)) << name << ": " << error;
    int suited = 0;
    for (const DisplaySystem& system : examples) suited += type.Unsuitable(system).empty();
    EXPECT_GT(suited, 0) << name << " suits none of the examples";
    for (const SolverOptionKey& key : CommonSolverOptionKeys()) EXPECT_TRUE(type.Reads(key.key)) << name;
    for (const SolverOptionKey& key : type.options) EXPECT_FALSE(key.meaning.empty()) << name << " " << key.key;
    EXPECT_FALSE(type.Reads("no_such_key")) << name;
  }
  EXPECT_TRUE(SolverRegistry::Builtins().get("hybrid").Reads("sub_iterations"));
  EXPECT_TRUE(SolverRegistry::Builtins().get("quasi-newton").Reads("warm_start_iterations"));
  EXPECT_FALSE(SolverRegistry::Builtins().get("multiplicative").Reads("sub_iterations"));
}

// The estimate's parts that differ between solvers, against the sizes by hand:
// the hybrid keeps one light field more (its chase: rays x 3 floats in whole
// 2 MB pages), and
// quasi-newton 9 + 4 x 2 vectors of doubles over the layer values beyond
// that; each with the workspace of its own passes (SolveWorkspace::Layout,
// tests/solve_memory_test.cpp) and the process as it is (left out here).
TEST(SolverRegistry, MemoryEstimateAddsWhatTheSolverStates) {
  const DisplaySystem system = CompileJson(testing::ReadExample("paper_prototype.json"));
  LightFieldGeometry dice;
  dice.cols = 400, dice.rows = 200, dice.views_x = 13, dice.views_y = 13;
  const double page = double(size_t(2) << 20);
  const double light_field = std::ceil(13.0 * 13 * 400 * 200 * 3 * 4 / page) * page;  // 163.6 MB
  double layer_values = 0;
  for (const VirtualLayer& layer : system.layers) layer_values += double(layer.cols) * layer.rows * 3;
  auto solver_own = [&](const std::string& solver, const SolverRegistry& r = SolverRegistry::Builtins()) {
    const MemoryEstimate e = EstimateSolveMemory(system, dice, solver, 2, r);
    const DisplayModel model(system, dice);
    EXPECT_EQ(e.workspace, SolveWorkspace::Layout(model, 2, r.get(solver).memory.passes).bytes()) << solver;
    return double(e.counted) - double(e.program) - double(e.workspace);
  };
  const double m = solver_own("multiplicative"), h = solver_own("hybrid"), q = solver_own("quasi-newton");
  EXPECT_NEAR(h - m, light_field, 2.0);
  // Quasi-newton: the warm start's chase, then 17 vectors of doubles in its place, each 7.68 MB in whole 2 MB pages.
  ASSERT_EQ(layer_values, 4.0 * 400 * 200 * 3);
  const double vector = 4.0 * page;
  EXPECT_NEAR(q - m, std::max(light_field, 17 * vector), 2.0);
  EXPECT_NE(EstimateSolveMemory(system, dice, "quasi-newton", 2)
                .breakdown.find("the larger of the solver's light fields 163.6 MB x 1 and the solver's layer vectors "
                                "142.6 MB (held in turn)"),
            std::string::npos);
  // The target once and the patterns (each layer's one heap block, in whole 4 KiB pages); the clipped copy stated
  // apart, since the target was not read.
  EXPECT_NEAR(m, light_field + 4 * std::ceil((400 * 200 * 3 * 4 + 16) / 4096.0) * 4096, 2.0);
  const MemoryEstimate hybrid = EstimateSolveMemory(system, dice, "hybrid", 2);
  EXPECT_FALSE(hybrid.clipped_copy_counted);
  EXPECT_NE(hybrid.breakdown.find("target 163.6 MB + the solver's light fields 163.6 MB x 1 + "), std::string::npos)
      << hybrid.breakdown;
  EXPECT_NE(hybrid.breakdown.find("(+ 163.6 MB for a clipped copy if the target exceeds the display's range)"),
            std::string::npos);
  const SolverRegistry r = WithNearFirst();
  EXPECT_EQ(solver_own("near-first", r), m);
}

Scene SceneWithSolve(const json& solve) {
  json doc = testing::ReadExample("multiplicative_2layer.json");
  doc["solve"] = solve;
  return ParseScene(doc, "examples/scene.json", ElementRegistry::WithBuiltins());
}

std::string SolveConfigError(const json& solve, const SolverRegistry& registry = SolverRegistry::Builtins()) {
  try {
    const Scene scene = SceneWithSolve(solve);
    ReadSolveConfig(scene, Compile(scene), registry);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(SolverRegistry, SceneKeysOfOtherSolversAreRefused) {
  EXPECT_EQ(SolveConfigError({{"sub_iterations", 2}}),
            "examples/scene.json: /solve/sub_iterations: the solver \"multiplicative\" does not read it (hybrid, "
            "quasi-newton do)");
  EXPECT_EQ(SolveConfigError({{"solver", "hybrid"}, {"warm_start_iterations", 2}}),
            "examples/scene.json: /solve/warm_start_iterations: the solver \"hybrid\" does not read it (quasi-newton "
            "do)");
  EXPECT_EQ(SolveConfigError({{"solver", "quasi-newton"}, {"warm_start_iterations", 2}, {"sub_iterations", 2}}), "");
  const Scene scene = SceneWithSolve({{"solver", "near-first"}, {"iterations", 7}});
  const SolveConfig c = ReadSolveConfig(scene, Compile(scene), WithNearFirst());
  EXPECT_EQ(c.solver, "near-first");
  EXPECT_EQ(c.options.iterations, 7);
  EXPECT_EQ(SolveConfigError({{"solver", "near-first"}}),
            "examples/scene.json: /solve/solver: unknown solver \"near-first\" Known solvers: additive-trust-region, "
            "hybrid, joint, multiplicative, quasi-newton");
}

// retinal_target: "traced" traces a target scene, so it is refused beside a light-field folder.
TEST(SolverRegistry, TracedRetinalTargetNeedsATargetScene) {
  const Scene scene = SceneWithSolve(
      {{"solver", "quasi-newton"}, {"objective", "retinal"}, {"retinal_target", "traced"}, {"target_scene", "t.json"}});
  EXPECT_EQ(ReadSolveConfig(scene, Compile(scene)).options.retinal.target, RetinalTarget::kTraced);
  EXPECT_EQ(SolveConfigError({{"solver", "quasi-newton"}, {"retinal_target", "traced"}, {"target", "dice"}}),
            "examples/scene.json: /solve/retinal_target: \"traced\" traces the target scene, and \"target\" is a "
            "light-field folder; give \"target_scene\"");
  EXPECT_EQ(SolveConfigError({{"solver", "quasi-newton"}, {"retinal_target", "exact"}}),
            "examples/scene.json: /solve/retinal_target: \"exact\" is not one of lightfield or traced");
}

// `compare` over every solver that suits each display: the registered one
// runs on the one-branch display, and not on the two-branch one.
TEST(SolverRegistry, CompareRunsARegisteredSolver) {
  const SolverRegistry registry = WithNearFirst();
  const DisplaySystem stack = CompileJson(ShrunkExample("multiplicative_2layer.json", 16, 8, 3));
  const DisplaySystem paper = CompileJson(ShrunkExample("paper_prototype.json", 16, 8, 3));
  const std::vector<std::string> for_stack = SuitableSolvers(stack, registry);
  const std::vector<std::string> for_paper = SuitableSolvers(paper, registry);
  EXPECT_EQ(for_stack, (std::vector<std::string>{"hybrid", "joint", "multiplicative", "near-first", "quasi-newton"}));
  EXPECT_EQ(for_paper, (std::vector<std::string>{"hybrid", "joint", "quasi-newton"}));

  const DisplayModel model(stack, DisplayLightFieldGeometry(stack));
  Patterns truth = model.UniformPatterns(0.5f);
  for (LayerPattern& p : truth)
    for (size_t k = 0; k < p.rgb.size(); ++k) p.rgb[k] = 0.3f + 0.6f * float((k * 7919) % 101) / 100.0f;
  const LightField target = Synthesize(model, truth);
  std::vector<CompareRun> runs;
  for (const std::string& solver : for_stack) {
    SolverOptions o = registry.get(solver).defaults;
    o.iterations = 3;
    runs.push_back({"stack", stack, solver, o, Sampling::kNearest});
  }
  const std::vector<CompareResult> results = RunComparison(runs, target, {}, registry);
  ASSERT_EQ(results.size(), for_stack.size());
  const CompareResult& near_first = results[3];
  EXPECT_EQ(near_first.solver, "near-first");
  EXPECT_EQ(near_first.report.solver, "near-first");
  EXPECT_TRUE(near_first.report.IsSolutionUsable()) << near_first.report.FullReport();
  EXPECT_EQ(near_first.report.iterations, 3);
  EXPECT_LT(near_first.report.final_objective, near_first.report.initial_objective);
  EXPECT_NE(CompareTable(results).find("near-first"), std::string::npos);
}

}  // namespace
}  // namespace layerlab
