// The contrast option table (analysis/contrast_option_table.h) against the
// consumers made from it in C++: its defaults are ContrastOptions' own, the
// "run.contrast" reader reads every scene key of the table and no other, with
// the table's ranges, and ContrastOptions::IsValid refuses exactly what lies
// outside each range. The command line and Python are held to it by
// tests/cli/option_table_flags.py and python/tests/test_option_tables.py,
// docs/scene-reference.md by docs.scene_reference_current.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <set>
#include <sstream>

#include "layerlab/analysis/contrast_option_table.h"
#include "layerlab/analysis/run_config.h"
#include "layerlab/framework/params.h"
#include "layerlab/systems/compile.h"
#include "layerlab/tests/option_range_values.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

using json = nlohmann::json;
using testing::InsideRange;
using testing::OutsideRange;

ContrastRunConfig ReadSection(const json& contrast) {
  json doc = testing::ReadExample("paper_prototype.json");
  doc["run"] = {{"contrast", contrast}};
  const Scene scene = ParseScene(doc, "examples/scene.json", ElementRegistry::WithBuiltins());
  return ReadRunConfig(scene, Compile(scene)).contrast;
}

std::string ReadError(const json& contrast) {
  try {
    ReadSection(contrast);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

json SceneValue(const ContrastOptionEntry& e, double v) { return testing::SceneValue(e, v, e.list != nullptr); }

void Set(const ContrastOptionEntry& e, ContrastOptions* o, double v) {
  if (e.integer) o->*e.integer = static_cast<int>(v);
  if (e.real) o->*e.real = v;
  if (e.list) o->*e.list = {v};
}

double Read(const ContrastOptionEntry& e, const ContrastOptions& o) {
  if (e.list) return (o.*e.list).at(0);
  return e.Number(o);
}

// The numbers of a default's text ("0.7, 1.3, 1.9 D", "0.01 deg", "24") in the field's unit.
std::vector<double> DefaultNumbers(const ContrastOptionEntry& e) {
  std::string text = e.default_text;
  if (!e.FieldUnit().empty()) {
    const std::string unit = " " + e.FieldUnit();
    EXPECT_EQ(text.substr(text.size() - unit.size()), unit) << e.key << ": " << text;
    text = text.substr(0, text.size() - unit.size());
  }
  std::vector<double> out;
  std::istringstream items(text);
  for (std::string item; std::getline(items, item, ',');) out.push_back(std::stod(item));
  return out;
}

TEST(ContrastOptionTable, KeysFlagsAndPythonNamesAreEachOnceAndEveryFieldHasItsAccess) {
  std::set<std::string> keys, flags, names;
  for (const ContrastOptionEntry& e : ContrastOptionTable()) {
    EXPECT_TRUE(keys.insert(e.key).second) << e.key;
    EXPECT_TRUE(e.cli_flag.empty() || flags.insert(e.cli_flag).second) << e.cli_flag;
    EXPECT_TRUE(e.python.empty() || names.insert(e.python).second) << e.python;
    EXPECT_FALSE(e.meaning.empty()) << e.key;
    EXPECT_FALSE(e.default_text.empty()) << e.key;
    switch (e.kind) {
      case OptionKind::kInteger:
        EXPECT_TRUE(e.integer && e.has_range) << e.key;
        break;
      case OptionKind::kReal:
        EXPECT_TRUE((e.real != nullptr) != (e.list != nullptr) && e.has_range) << e.key;
        break;
      case OptionKind::kChoice:
        EXPECT_TRUE(e.get && e.set && e.choices.size() >= 2) << e.key;
        break;
      case OptionKind::kBoolean:
        EXPECT_TRUE(e.get && e.set) << e.key;
        break;
      case OptionKind::kSeed:
        ADD_FAILURE() << e.key << ": the contrast sweep has no seed";
        break;
      case OptionKind::kConfig:
        EXPECT_FALSE(e.integer || e.real || e.list || e.get) << e.key;
        break;
    }
    // Not in the scene: a keyword Python sets itself, which it can for choices and switches only.
    if (!e.in_scene) {
      EXPECT_TRUE(e.kind == OptionKind::kChoice || e.kind == OptionKind::kBoolean) << e.key;
    }
  }
  std::string why;
  EXPECT_TRUE(ContrastOptions{}.IsValid(&why)) << why;
}

TEST(ContrastOptionTable, TheDefaultsAreTheOptionsOwn) {
  const ContrastOptions defaults;
  for (const ContrastOptionEntry& e : ContrastOptionTable()) {
    if (e.kind == OptionKind::kInteger || e.kind == OptionKind::kReal) {
      const std::vector<double> table = DefaultNumbers(e);
      const std::vector<double> field = e.list ? defaults.*e.list : std::vector<double>{e.Number(defaults)};
      EXPECT_EQ(table, field) << e.key << ": the table says " << e.default_text;
    }
    if (e.kind == OptionKind::kChoice) {
      EXPECT_EQ(e.choices.at(e.get(defaults)), e.default_text) << e.key;
    }
    if (e.kind == OptionKind::kBoolean) {
      EXPECT_EQ(e.get(defaults) ? "true" : "false", e.default_text) << e.key;
    }
  }
  const ContrastOptionEntry& accommodation = *FindContrastOption("accommodation");
  std::ostringstream sweep;
  sweep << defaults.accommodation_min_diopters << " D to " << defaults.accommodation_max_diopters << " D by "
        << defaults.accommodation_step_diopters << " D";
  EXPECT_EQ(accommodation.default_text, sweep.str());
}

// Options in which `e`'s relations to the others hold across its range: the eyebox grid's step describes the
// grid of the largest range.
ContrastOptions Base(const ContrastOptionEntry& e) {
  ContrastOptions o;
  if (e.key == "eyebox_step") o.eyebox_range_m = kMaxContrastEyeboxRange;
  return o;
}

TEST(ContrastOptionTable, IsValidRefusesExactlyWhatLiesOutsideEachRange) {
  for (const ContrastOptionEntry& e : ContrastOptionTable()) {
    if (!e.has_range) continue;
    const bool integer = e.kind == OptionKind::kInteger;
    const std::string field = e.list ? e.key + "[0]: " : e.key + ": ";
    for (bool at_min : {true, false}) {
      ContrastOptions o = Base(e);
      std::string why;
      Set(e, &o, InsideRange(e.range, integer, at_min));
      EXPECT_TRUE(o.IsValid(&why)) << e.key << " at " << InsideRange(e.range, integer, at_min) << ": " << why;
      Set(e, &o, OutsideRange(e.range, integer, at_min));
      ASSERT_FALSE(o.IsValid(&why)) << e.key << " at " << OutsideRange(e.range, integer, at_min);
      EXPECT_EQ(why.substr(0, field.size()), field) << why;
      EXPECT_NE(why.find(e.Constraint()), std::string::npos) << why;
    }
    if (integer) continue;
    ContrastOptions o = Base(e);
    std::string why;
    Set(e, &o, std::numeric_limits<double>::quiet_NaN());
    EXPECT_FALSE(o.IsValid(&why)) << e.key << " at nan";
  }
  ContrastOptions o;
  std::string why;
  o.accommodation_step_diopters = 0;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_EQ(why, "accommodation.step: 0: must be above 0 D");
  o = ContrastOptions{};
  o.accommodation_max_diopters = o.accommodation_min_diopters;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_EQ(why, "accommodation.to: 0: must be beyond accommodation.from (0.00 D)");
}

TEST(ContrastOptionTable, TheSceneReaderReadsTheTablesKeysWithTheirRanges) {
  ParamsKeyRecorder recorder;
  ReadSection(json::object());
  std::set<std::string> table;
  for (const ContrastOptionEntry& e : ContrastOptionTable())
    if (e.in_scene) table.insert(e.key);
  EXPECT_EQ(recorder.keys().at("/run/contrast"), table);

  for (const ContrastOptionEntry& e : ContrastOptionTable()) {
    const std::string at = "/run/contrast/" + e.key + (e.list ? "/0: " : ": ");
    if (!e.in_scene) {
      EXPECT_NE(ReadError({{e.key, e.kind == OptionKind::kBoolean ? json(true) : json(e.choices.at(0))}})
                    .find("/run/contrast/" + e.key + ": unknown key \"" + e.key + "\""),
                std::string::npos)
          << e.key << " is not a scene key: " << ReadError({{e.key, true}});
      continue;
    }
    if (!e.has_range || e.kind == OptionKind::kConfig) continue;
    const bool integer = e.kind == OptionKind::kInteger;
    const double step = (e.range.max - e.range.min) * 1e-3;  // clear of the retina's sample count
    for (bool at_min : {true, false}) {
      const double inside = InsideRange(e.range, integer, at_min, step);
      const double outside = OutsideRange(e.range, integer, at_min, step);
      EXPECT_EQ(ReadError({{e.key, SceneValue(e, inside)}}), "") << e.key << " at " << inside;
      if (ReadError({{e.key, SceneValue(e, inside)}}).empty()) {
        EXPECT_NEAR(Read(e, ReadSection({{e.key, SceneValue(e, inside)}}).options), inside,
                    1e-12 * (1 + std::abs(inside)))
            << e.key;
      }
      const std::string refused = ReadError({{e.key, SceneValue(e, outside)}});
      EXPECT_NE(refused.find(at), std::string::npos) << e.key << " at " << outside << ": " << refused;
    }
  }
}

}  // namespace
}  // namespace layerlab
