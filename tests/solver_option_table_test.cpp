// The solver option table (solvers/solver_option_table.h) against two of the
// consumers made from it: the scene reader (ReadSolveConfig) reads every
// scene key of the table, no other, with the table's range and choices, and
// SolverOptions::IsValid refuses exactly what lies outside each range. The
// command line and Python are held to it by tests/cli/solver_option_flags.py
// and python/tests/test_solver_option_table.py, docs/scene-reference.md by
// docs.scene_reference_current.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <set>

#include "layerlab/framework/params.h"
#include "layerlab/solvers/solve_config.h"
#include "layerlab/solvers/solver_option_table.h"
#include "layerlab/systems/compile.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

using json = nlohmann::json;

// quasi-newton reads every solver option of the section (sub_iterations and warm_start_iterations too).
Scene SceneWithSolve(json solve) {
  json doc = testing::ReadExample("multiplicative_2layer.json");
  solve["solver"] = "quasi-newton";
  doc["solve"] = solve;
  return ParseScene(doc, "examples/scene.json", ElementRegistry::WithBuiltins());
}

SolveConfig ReadSection(const json& solve) {
  const Scene scene = SceneWithSolve(solve);
  return ReadSolveConfig(scene, Compile(scene));
}

std::string ReadError(const json& solve) {
  try {
    ReadSection(solve);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

// Values just inside and just outside a range (integers step by 1).
double Inside(const OptionRange& r, bool integer, bool at_min) {
  const double end = at_min ? r.min : r.max, toward = at_min ? r.max : r.min;
  if (!(at_min ? r.min_open : r.max_open)) return end;
  return integer ? end + (at_min ? 1 : -1) : std::nextafter(end, toward);
}
double Outside(const OptionRange& r, bool integer, bool at_min) {
  const double end = at_min ? r.min : r.max, away = at_min ? -INFINITY : INFINITY;
  if (at_min ? r.min_open : r.max_open) return end;
  return integer ? end + (at_min ? -1 : 1) : std::nextafter(end, away);
}

void Set(const SolverOptionEntry& e, SolverOptions* o, double v) {
  if (e.integer) o->*e.integer = static_cast<int>(v);
  if (e.real) o->*e.real = v;
}

TEST(SolverOptionTable, KeysFlagsAndPythonNamesAreEachOnceAndEveryFieldHasItsAccess) {
  std::set<std::string> keys, flags, names;
  for (const SolverOptionEntry& e : SolverOptionTable()) {
    EXPECT_TRUE(keys.insert(e.key).second) << e.key;
    EXPECT_TRUE(e.cli_flag.empty() || flags.insert(e.cli_flag).second) << e.cli_flag;
    EXPECT_TRUE(e.python.empty() || names.insert(e.python).second) << e.python;
    EXPECT_FALSE(e.meaning.empty()) << e.key;
    EXPECT_FALSE(e.default_text.empty()) << e.key;
    switch (e.kind) {
      case SolverOptionKind::kInteger:
        EXPECT_TRUE(e.integer && e.has_range) << e.key;
        break;
      case SolverOptionKind::kReal:
        EXPECT_TRUE(e.real && e.has_range) << e.key;
        break;
      case SolverOptionKind::kSeed:
        EXPECT_TRUE(e.seed) << e.key;
        break;
      case SolverOptionKind::kChoice:
        EXPECT_TRUE(e.get && e.set && e.choices.size() >= 2) << e.key;
        break;
      case SolverOptionKind::kBoolean:
        EXPECT_TRUE(e.get && e.set) << e.key;
        break;
      case SolverOptionKind::kConfig:
        break;
    }
  }
  // Every solver's defaults lie inside the table's ranges.
  for (const std::string& name : SolverRegistry::Builtins().names()) {
    std::string why;
    EXPECT_TRUE(SolverRegistry::Builtins().get(name).defaults.IsValid(&why)) << name << ": " << why;
  }
}

// Options in which `e`'s relations to the others hold across its range: the eyebox grid's keys describe the
// retinal objective's grid of the largest range.
SolverOptions Base(const SolverOptionEntry& e) {
  SolverOptions o;
  if (e.key.rfind("eyebox_", 0) == 0) o.objective = ObjectiveKind::kRetinal, o.eyebox_range_m = kMaxEyeboxRange;
  return o;
}

TEST(SolverOptionTable, IsValidRefusesExactlyWhatLiesOutsideEachRange) {
  for (const SolverOptionEntry& e : SolverOptionTable()) {
    if (!e.has_range) continue;
    const bool integer = e.kind == SolverOptionKind::kInteger;
    for (bool at_min : {true, false}) {
      SolverOptions o = Base(e);
      std::string why;
      Set(e, &o, Inside(e.range, integer, at_min));
      EXPECT_TRUE(o.IsValid(&why)) << e.key << " at " << Inside(e.range, integer, at_min) << ": " << why;
      Set(e, &o, Outside(e.range, integer, at_min));
      ASSERT_FALSE(o.IsValid(&why)) << e.key << " at " << Outside(e.range, integer, at_min);
      EXPECT_EQ(why.substr(0, e.key.size() + 2), e.key + ": ") << why;
      EXPECT_NE(why.find(e.Constraint()), std::string::npos) << why;
    }
    if (!e.real) continue;
    SolverOptions o = Base(e);
    std::string why;
    Set(e, &o, std::numeric_limits<double>::quiet_NaN());
    EXPECT_FALSE(o.IsValid(&why)) << e.key << " at nan";
  }
}

TEST(SolverOptionTable, TheSceneReaderReadsTheTablesKeysWithTheirRangesAndChoices) {
  // The keys it asks for: the table's scene keys, no other.
  ParamsKeyRecorder recorder;
  ReadSection(json::object());
  std::set<std::string> table;
  for (const SolverOptionEntry& e : SolverOptionTable())
    if (e.in_scene) table.insert(e.key);
  EXPECT_EQ(recorder.keys().at("/solve"), table);

  for (const SolverOptionEntry& e : SolverOptionTable()) {
    if (!e.in_scene) continue;
    const std::string at = "/solve/" + e.key + ": ";
    if (e.has_range) {
      const bool integer = e.kind == SolverOptionKind::kInteger;
      for (bool at_min : {true, false}) {
        const double inside = Inside(e.range, integer, at_min), outside = Outside(e.range, integer, at_min);
        json in = {{e.key, inside}}, out = {{e.key, outside}};
        if (integer) in = {{e.key, int64_t(inside)}}, out = {{e.key, int64_t(outside)}};
        EXPECT_EQ(ReadError(in), "") << e.key << " at " << inside;
        if (integer || e.real) {
          SolverOptions read = ReadSection(in).options;
          EXPECT_EQ(e.Number(read), inside) << e.key;
        }
        EXPECT_NE(ReadError(out).find(at), std::string::npos) << e.key << " at " << outside << ": " << ReadError(out);
      }
    }
    if (e.kind == SolverOptionKind::kChoice) {
      for (size_t i = 0; i < e.choices.size(); ++i) {
        json solve = {{e.key, e.choices[i]}};
        if (e.key == "retinal_target") solve["target_scene"] = "t.json";
        EXPECT_EQ(e.get(ReadSection(solve).options), int(i)) << e.key << " " << e.choices[i];
      }
      EXPECT_NE(ReadError({{e.key, "none-of-these"}}).find(at + "\"none-of-these\" is not one of " + e.ChoiceList()),
                std::string::npos)
          << ReadError({{e.key, "none-of-these"}});
    }
    if (e.kind == SolverOptionKind::kBoolean) {
      json solve = {{e.key, true}};
      if (e.key == "contrast_sensitivity") solve["objective"] = "retinal";
      EXPECT_EQ(e.get(ReadSection(solve).options), 1) << e.key;
    }
    if (e.kind == SolverOptionKind::kSeed) {
      EXPECT_EQ(ReadSection({{e.key, UINT64_MAX}}).options.seed, UINT64_MAX);
      EXPECT_NE(ReadError({{e.key, -1}}).find(at), std::string::npos);
    }
  }
}

}  // namespace
}  // namespace layerlab
