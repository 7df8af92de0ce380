// The "run" section (docs/run-section.md): defaults that follow the display,
// values with units, and bad input refused with its location (verbatim).
#include <cmath>

#include "layerlab/analysis/run_config.h"
#include "layerlab/solvers/solve_config.h"
#include "layerlab/systems/scene.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

using nlohmann::json;

struct Loaded {
  Scene scene;
  DisplaySystem system;
};

Loaded Load(const json& run, const json& solve = nullptr) {
  json doc = testing::ReadExample("paper_prototype.json");
  doc.erase("run");
  doc.erase("solve");
  if (!run.is_null()) doc["run"] = run;
  if (!solve.is_null()) doc["solve"] = solve;
  Scene scene = ParseScene(doc, "examples/scene.json", ElementRegistry::WithBuiltins());
  DisplaySystem system = Compile(scene);
  return {std::move(scene), std::move(system)};
}

std::string RunError(const json& run) {
  try {
    Loaded l = Load(run);
    ReadRunConfig(l.scene, l.system);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(RunConfig, NothingDeclaredRunsNothing) {
  Loaded l = Load(nullptr);
  RunConfig c = ReadRunConfig(l.scene, l.system);
  EXPECT_FALSE(c.declared);
  EXPECT_FALSE(c.retina.enabled);
  EXPECT_FALSE(c.contrast.enabled);
  EXPECT_FALSE(c.compare.enabled);
}

TEST(RunConfig, RetinaDefaultsToTheLayerDepths) {
  Loaded l = Load({{"retina", json::object()}});
  RunConfig c = ReadRunConfig(l.scene, l.system);
  ASSERT_TRUE(c.retina.enabled);
  ASSERT_EQ(c.retina.accommodation_diopters.size(), 4u);
  EXPECT_TRUE(testing::Close(c.retina.accommodation_diopters[0], 0.4, 1e-9));
  EXPECT_TRUE(testing::Close(c.retina.accommodation_diopters[3], 2.2, 1e-9));
  EXPECT_EQ(c.retina.resolution_deg, 0.05);
  EXPECT_TRUE(c.retina.natural);
  EXPECT_FALSE(c.retina.natural_traced);
  EXPECT_FALSE(c.contrast.enabled);
}

TEST(RunConfig, NaturalViewingReadsTheLightFieldUnlessTraced) {
  Loaded l = Load({{"retina", {{"natural_viewing", "traced"}}}});
  EXPECT_TRUE(ReadRunConfig(l.scene, l.system).retina.natural_traced);
  EXPECT_EQ(RunError({{"retina", {{"natural_viewing", "ray traced"}}}}),
            "examples/scene.json: /run/retina/natural_viewing: \"ray traced\" is not one of light field or traced");
}

TEST(RunConfig, FocalStackMergesWithTheStates) {
  Loaded l = Load({{"retina",
                    {{"accommodation", {"1.0 D", "0.5 m"}},
                     {"focal_stack", {{"from", "0 D"}, {"to", "2 D"}, {"step", "0.5 D"}}},
                     {"resolution", "3 arcmin"}}}});
  RetinaRunConfig r = ReadRunConfig(l.scene, l.system).retina;
  std::vector<double> states = r.states();  // 0, 0.5, 1, 1.5, 2 (1 and 2 D once each)
  ASSERT_EQ(states.size(), 5u);
  EXPECT_TRUE(testing::Close(states[4], 2.0, 1e-12));
  EXPECT_TRUE(testing::Close(r.resolution_deg, 0.05, 1e-12));
}

TEST(RunConfig, ContrastAndCompareReadUnitsAndResolvePaths) {
  Loaded l = Load({{"contrast",
                    {{"depths", {"0.7 D"}},
                     {"frequencies", {"2 cpd", 4}},
                     {"accommodation", {{"from", "0 D"}, {"to", "2.6 D"}, {"step", "0.1 D"}}},
                     {"retina_resolution", "0.02 deg"}}},
                   {"compare",
                    {{"scenes", {"hybrid_pbs_hwp.json"}},
                     {"solvers", {"hybrid", "joint"}},
                     {"iterations", 5},
                     {"objectives", {"retinal", "lightfield"}}}}});
  RunConfig c = ReadRunConfig(l.scene, l.system);
  ASSERT_EQ(c.contrast.options.frequencies_cpd.size(), 2u);
  EXPECT_EQ(c.contrast.options.frequencies_cpd[1], 4.0);
  EXPECT_TRUE(testing::Close(c.contrast.options.accommodation_step_diopters, 0.1, 1e-9));
  EXPECT_TRUE(testing::Close(c.contrast.options.retina_resolution_deg, 0.02, 1e-12));
  ASSERT_EQ(c.compare.scenes.size(), 1u);
  EXPECT_EQ(c.compare.scenes[0], "examples/hybrid_pbs_hwp.json");
  EXPECT_EQ(c.compare.iterations.value_or(0), 5);
  EXPECT_EQ(c.compare.objectives, (std::vector<ObjectiveKind>{ObjectiveKind::kRetinal, ObjectiveKind::kLightField}));
}

TEST(RunConfig, BadInputIsRefusedWithItsLocation) {
  EXPECT_EQ(
      RunError({{"retina", {{"accomodation", {"1 D"}}}}}),
      "examples/scene.json: /run/retina/accomodation: unknown key \"accomodation\"; did you mean \"accommodation\"?");
  EXPECT_EQ(RunError({{"retna", json::object()}}),
            "examples/scene.json: /run/retna: unknown key \"retna\"; did you mean \"retina\"?");
  EXPECT_EQ(RunError({{"retina", {{"accommodation", {"1 D", 1.5}}}}}),
            "examples/scene.json: /run/retina/accommodation/1: expected a depth with its unit, such as \"0.4 D\" or "
            "\"2.5 m\", got a number");
  EXPECT_EQ(RunError({{"retina", {{"focal_stack", {{"from", "2 D"}, {"to", "1 D"}, {"step", "0.1 D"}}}}}}),
            "examples/scene.json: /run/retina/focal_stack/to: 1.00 D is not beyond \"from\" (2.00 D)");
  EXPECT_EQ(RunError({{"retina", {{"focal_stack", {{"from", "0 D"}, {"to", "1 D"}, {"step", "0 D"}}}}}}),
            "examples/scene.json: /run/retina/focal_stack/step: 0.000 D: give a step above 0 and at most to - from "
            "(1.00 D)");
  EXPECT_EQ(
      RunError({{"contrast", {{"frequencies", {"2 cpd", "4 deg"}}}}}),
      "examples/scene.json: /run/contrast/frequencies/1: 'deg' is an angle unit; expected an angular frequency in "
      "cpd");
  EXPECT_EQ(RunError({{"compare", {{"solvers", {"hybird"}}}}}),
            "examples/scene.json: /run/compare/solvers/0: unknown solver \"hybird\"; did you mean \"hybrid\"? Known "
            "solvers: additive-trust-region, hybrid, joint, multiplicative, quasi-newton");
  EXPECT_EQ(RunError({{"compare", {{"objectives", {"lightfield", "retina"}}}}}),
            "examples/scene.json: /run/compare/objectives/1: \"retina\" is not one of lightfield or retinal");
  EXPECT_EQ(RunError({{"compare", {{"objectives", json::array()}}}}),
            "examples/scene.json: /run/compare/objectives: expected a non-empty array, got an array");
  for (const char* section : {"retina", "compare"}) {
    const std::string error = RunError({{section, {{"jnd_minkowski_exponent", 0.5}}}});
    EXPECT_NE(error.find(std::string("/run/") + section + "/jnd_minkowski_exponent"), std::string::npos) << error;
    EXPECT_NE(RunError({{section, {{"fovea", {"2 deg"}}}}}).find("/run/" + std::string(section) + "/fovea"),
              std::string::npos);
  }
  EXPECT_EQ(RunError({{"compare", {{"fovea", {"2 deg", "1 deg"}}}}}),
            "examples/scene.json: /run/compare/fovea: sets how the focal stack's metrics are measured: give "
            "\"metrics\" too");
}

TEST(SolveConfig, TargetSceneIsResolvedAndExclusive) {
  Loaded l = Load(nullptr, {{"target_scene", "targets/dice.json"}});
  SolveConfig c = ReadSolveConfig(l.scene, l.system);
  EXPECT_EQ(c.target_scene, "examples/targets/dice.json");
  EXPECT_EQ(c.target, "");
  Loaded both = Load(nullptr, {{"target_scene", "targets/dice.json"}, {"target", "lf"}});
  try {
    ReadSolveConfig(both.scene, both.system);
    FAIL() << "both targets were accepted";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()),
              "examples/scene.json: /solve/target_scene: give \"target\" (a light-field folder) or \"target_scene\" (a "
              "target scene to render), not both");
  }
}

}  // namespace
}  // namespace layerlab
