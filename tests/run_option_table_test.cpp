// The run option tables (analysis/run_option_table.h) against the consumers
// made from them: the run section's reader reads every key of each table and
// no other, with the table's ranges; the defaults are the structs' own; and
// IsValid refuses exactly what lies outside each range. docs/scene-reference.md
// is held to them by docs.scene_reference_current.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <set>

#include "layerlab/analysis/frame_sequence.h"
#include "layerlab/analysis/run_config.h"
#include "layerlab/analysis/run_option_table.h"
#include "layerlab/framework/params.h"
#include "layerlab/systems/compile.h"
#include "layerlab/tests/option_range_values.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

using json = nlohmann::json;
using testing::InsideRange;
using testing::OutsideRange;

struct Loaded {
  Scene scene;
  DisplaySystem system;
};

Loaded Load(const json& run) {
  json doc = testing::ReadExample("paper_prototype.json");
  doc["run"] = run;
  Scene scene = ParseScene(doc, "examples/scene.json", ElementRegistry::WithBuiltins());
  DisplaySystem system = Compile(scene);
  return {std::move(scene), std::move(system)};
}

RunConfig Read(const json& run) {
  Loaded l = Load(run);
  return ReadRunConfig(l.scene, l.system);
}

std::string ReadError(const json& run) {
  try {
    Read(run);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

template <class Options>
void ExpectWellFormed(const std::vector<OptionEntry<Options>>& table) {
  std::set<std::string> keys;
  for (const OptionEntry<Options>& e : table) {
    EXPECT_TRUE(keys.insert(e.key).second) << e.key;
    EXPECT_FALSE(e.meaning.empty() || e.default_text.empty() || e.type.empty()) << e.key;
    EXPECT_TRUE(e.in_scene) << e.key;
    // The run section has no flags or keywords of its own: one here would have no consumer.
    EXPECT_TRUE(e.cli_flag.empty() && e.python.empty()) << e.key;
    if (e.kind == OptionKind::kReal) {
      EXPECT_TRUE((e.real != nullptr) != (e.list != nullptr) && e.has_range) << e.key;
    }
    if (e.kind == OptionKind::kChoice || e.kind == OptionKind::kBoolean) {
      EXPECT_TRUE(e.get && e.set) << e.key;
    }
    if (e.kind == OptionKind::kChoice) {
      EXPECT_EQ(e.choices.at(e.get(Options{})), e.default_text) << e.key;
    }
    if (e.kind == OptionKind::kBoolean) {
      EXPECT_EQ(e.get(Options{}) ? "true" : "false", e.default_text) << e.key;
    }
    if (e.kind == OptionKind::kConfig) {
      EXPECT_FALSE(e.integer || e.real || e.list || e.get) << e.key;
    }
  }
}

TEST(RunOptionTable, EachTableIsWellFormedAndItsDefaultsAreTheStructsOwn) {
  ExpectWellFormed(RunOptionTable());
  ExpectWellFormed(RetinaRunOptionTable());
  ExpectWellFormed(CompareRunOptionTable());
  ExpectWellFormed(FramesRunOptionTable());
  EXPECT_EQ(FramesRunConfig{}.sequence().frame_iterations, FrameSequenceOptions{}.frame_iterations);
  EXPECT_EQ(FramesRunConfig{}.sequence().cold_every, FrameSequenceOptions{}.cold_every);
  const RetinaRunOptionEntry& resolution = RetinaRunOption("resolution");
  EXPECT_EQ(ParseQuantity(resolution.default_text, Dimension::kAngle) / resolution.FieldUnitInSI(),
            RetinaRunConfig{}.resolution_deg);
  std::string why;
  EXPECT_TRUE(RunConfig{}.IsValid(&why)) << why;
}

TEST(RunOptionTable, TheReaderReadsEachTablesKeysAndNoOther) {
  ParamsKeyRecorder recorder;
  Read({{"retina", json::object()}, {"compare", json::object()}, {"frames", {{"count", 2}}}});
  auto keys = [](const auto& table) {
    std::set<std::string> out;
    for (const auto& e : table) out.insert(e.key);
    return out;
  };
  EXPECT_EQ(recorder.keys().at("/run"), keys(RunOptionTable()));
  EXPECT_EQ(recorder.keys().at("/run/retina"), keys(RetinaRunOptionTable()));
  EXPECT_EQ(recorder.keys().at("/run/compare"), keys(CompareRunOptionTable()));
  EXPECT_EQ(recorder.keys().at("/run/frames"), keys(FramesRunOptionTable()));
}

TEST(RunOptionTable, FramesNeedACountAndHoldEachValueToItsRange) {
  EXPECT_NE(ReadError({{"frames", json::object()}}).find("/run/frames/count: is required"), std::string::npos)
      << ReadError({{"frames", json::object()}});
  const RunConfig read = Read({{"frames", {{"count", 60}, {"frame_iterations", 1}, {"cold_every", 10}}}});
  EXPECT_TRUE(read.frames.enabled);
  EXPECT_EQ(read.frames.sequence().frames, 60);
  EXPECT_EQ(read.frames.sequence().frame_iterations, 1);
  EXPECT_EQ(read.frames.sequence().cold_every, 10);
  for (const FramesRunOptionEntry& e : FramesRunOptionTable())
    for (bool at_min : {true, false}) {
      const int inside = int(InsideRange(e.range, true, at_min, 1)),
                outside = int(OutsideRange(e.range, true, at_min, 1));
      json in = {{"count", 2}}, out = {{"count", 2}};
      in[e.key] = inside, out[e.key] = outside;
      EXPECT_EQ(ReadError({{"frames", in}}), "") << e.key << " at " << inside;
      EXPECT_NE(ReadError({{"frames", out}}).find("/run/frames/" + e.key + ": "), std::string::npos)
          << e.key << " at " << outside << ": " << ReadError({{"frames", out}});
      FramesRunConfig f;
      f.count = 2;
      f.*e.integer = outside;
      std::string why;
      EXPECT_FALSE(f.IsValid(&why)) << e.key << " at " << outside;
      EXPECT_EQ(why.rfind(e.key, 0), 0u) << why;
    }
}

// Inside each range read, outside refused at the key, for the entries of `table` under /run/`object`.
template <class Options>
void ExpectRangesRead(const std::vector<OptionEntry<Options>>& table, const std::string& object) {
  for (const OptionEntry<Options>& e : table) {
    if (!e.has_range) continue;
    const bool integer = e.type == "integer", pair = e.key == "field";
    const std::string at = "/run/" + object + "/" + e.key + (e.list ? "/0: " : ": ");
    const double step = (e.range.max - e.range.min) * 1e-3;
    for (bool at_min : {true, false}) {
      const double inside = InsideRange(e.range, integer, at_min, step);
      const double outside = OutsideRange(e.range, integer, at_min, step);
      const json in = {{object, {{e.key, testing::SceneValue(e, inside, e.list != nullptr, pair)}}}};
      const json out = {{object, {{e.key, testing::SceneValue(e, outside, e.list != nullptr, pair)}}}};
      EXPECT_EQ(ReadError(in), "") << e.key << " at " << inside;
      const std::string refused = ReadError(out);
      EXPECT_NE(refused.find(at), std::string::npos) << e.key << " at " << outside << ": " << refused;
    }
  }
}

TEST(RunOptionTable, TheReaderHoldsEachValueToItsRange) {
  ExpectRangesRead(RetinaRunOptionTable(), "retina");
  ExpectRangesRead(CompareRunOptionTable(), "compare");
  EXPECT_NEAR(Read({{"retina", {{"resolution", "0.02 deg"}, {"field", {"3 deg", "2 deg"}}}}}).retina.field_y_deg, 2,
              1e-12);
}

TEST(RunOptionTable, IsValidRefusesExactlyWhatLiesOutsideEachRange) {
  for (const RetinaRunOptionEntry& e : RetinaRunOptionTable()) {
    if (!e.has_range) continue;
    for (bool at_min : {true, false}) {
      for (bool outside : {false, true}) {
        const double v = outside ? OutsideRange(e.range, false, at_min) : InsideRange(e.range, false, at_min);
        RetinaRunConfig r;
        if (e.real) r.*e.real = v;
        if (e.list) r.*e.list = {v};
        if (e.key == "field") r.field_x_deg = v, r.field_y_deg = 10;
        std::string why;
        EXPECT_EQ(r.IsValid(&why), !outside) << e.key << " at " << v << ": " << why;
        if (outside) {
          EXPECT_EQ(why.find(e.Constraint()) != std::string::npos && why.rfind(e.key, 0) == 0, true) << why;
        }
      }
    }
  }
  for (const CompareRunOptionEntry& e : CompareRunOptionTable()) {
    if (!e.has_range) continue;
    const bool integer = e.type == "integer";
    for (bool at_min : {true, false}) {
      for (bool outside : {false, true}) {
        const double v = outside ? OutsideRange(e.range, integer, at_min) : InsideRange(e.range, integer, at_min);
        CompareRunConfig c;
        if (e.key == "iterations") c.iterations = int(v);
        if (e.key == "time_budget") c.time_budget_s = v;
        std::string why;
        EXPECT_EQ(c.IsValid(&why), !outside) << e.key << " at " << v << ": " << why;
        if (outside) {
          EXPECT_EQ(why, OptionViolation(e.key, v, e.Constraint()));
        }
      }
    }
  }
  RetinaRunConfig nan;
  nan.resolution_deg = std::numeric_limits<double>::quiet_NaN();
  std::string why;
  EXPECT_FALSE(nan.IsValid(&why));
}

}  // namespace
}  // namespace layerlab
