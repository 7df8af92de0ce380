// docs/scene-reference.md is made from key tables in the sources; these tests
// hold the tables to the code: every key the code asks for (framework/params.h
// records them) is in its table, and every key a table lists is asked for,
// over every shipped example scene and tests/data/fold_mirror_scene.json.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <set>

#include "layerlab/analysis/run_config.h"
#include "layerlab/framework/json_file.h"
#include "layerlab/solvers/solve_config.h"
#include "layerlab/systems/compile.h"
#include "layerlab/tests/test_util.h"
#include "layerlab/tools/key_tables.h"
#include "layerlab/tools/scene_reference.h"

namespace layerlab {
namespace {

namespace fs = std::filesystem;
using KeySets = std::map<std::string, std::set<std::string>>;  // section -> keys

std::vector<std::string> SceneFiles() {
  std::vector<std::string> files;
  for (const char* folder : {"examples", "examples/small"})
    for (const auto& entry : fs::directory_iterator(std::string(LAYERLAB_SOURCE_DIR) + "/" + folder))
      if (entry.path().extension() == ".json" &&
          ReadJsonFile(entry.path().string()).value("format", "") == std::string("layerlab-scene/1"))
        files.push_back(entry.path().string());
  files.push_back(std::string(LAYERLAB_SOURCE_DIR) + "/tests/data/fold_mirror_scene.json");
  return files;
}

// The section a recorded JSON pointer belongs to ("" when no table covers it:
// array items, spectral tables, an active region).
std::string SectionOf(const std::string& pointer, const nlohmann::json& document) {
  static const std::map<std::string, std::string> fixed = {{"", "scene"},
                                                           {"/solve", "solve"},
                                                           {"/run", "run"},
                                                           {"/run/retina", "run.retina"},
                                                           {"/run/contrast", "run.contrast"},
                                                           {"/run/compare", "run.compare"},
                                                           {"/run/retina/focal_stack", "depth_range"},
                                                           {"/run/contrast/accommodation", "depth_range"}};
  if (auto it = fixed.find(pointer); it != fixed.end()) return it->second;
  const std::string prefix = "/elements/";
  if (pointer.rfind(prefix, 0) != 0) return "";
  const size_t slash = pointer.find('/', prefix.size());
  const std::string type = document["elements"][std::stoul(pointer.substr(prefix.size()))]["type"].get<std::string>();
  if (slash == std::string::npos) return type;
  const std::string inside = pointer.substr(slash);  // a lens's surfaces: "/surfaces/2"
  if (inside.rfind("/surfaces/", 0) == 0 && inside.find('/', 10) == std::string::npos) return type + ".surface";
  return "";
}

// Every key the code asks for, per section, over all the scene files.
KeySets KeysTheCodeReads(std::set<std::string>* covered_files) {
  KeySets read;
  for (const std::string& file : SceneFiles()) {
    ParamsKeyRecorder recorder;
    Scene scene = LoadScene(file);
    DisplaySystem system = Compile(scene);
    ReadSolveConfig(scene, system);
    ReadRunConfig(scene, system);
    for (const auto& [pointer, keys] : recorder.keys()) {
      std::string section = SectionOf(pointer, scene.document);
      if (section.empty()) continue;
      read[section].insert(keys.begin(), keys.end());
    }
    covered_files->insert(file);
  }
  return read;
}

TEST(SceneReference, EveryKeyTheCodeReadsIsInItsTableAndEveryListedKeyIsRead) {
  std::vector<KeyTable> tables = SceneReferenceTables(LAYERLAB_SOURCE_DIR);
  std::set<std::string> files;
  KeySets read = KeysTheCodeReads(&files);
  std::set<std::string> common;  // the registry reads "type" and "name" of every element
  for (const KeyTable& t : tables)
    if (t.section == "element")
      for (const std::string& key : t.keys()) common.insert(key);
  ASSERT_EQ(common, (std::set<std::string>{"type", "name"}));
  const ElementRegistry registry = ElementRegistry::WithBuiltins();
  for (const KeyTable& t : tables) {
    if (t.section == "element") continue;
    const std::vector<std::string> keys = t.keys();
    std::set<std::string> listed(keys.begin(), keys.end());
    if (registry.find(t.section)) listed.insert(common.begin(), common.end());
    ASSERT_TRUE(read.count(t.section)) << "no scene file exercises " << t.section
                                       << "; add it to tests/data/fold_mirror_scene.json";
    for (const std::string& key : read[t.section])
      EXPECT_TRUE(listed.count(key)) << "the code reads \"" << key << "\" of " << t.section << " but the key table in "
                                     << t.file << " does not list it";
    for (const std::string& key : listed)
      EXPECT_TRUE(read[t.section].count(key)) << "the key table in " << t.file << " lists \"" << key << "\" of "
                                              << t.section << ", which the code never reads";
  }
  EXPECT_GE(files.size(), 10u);
}

TEST(SceneReference, TheRecorderSeesKeysAskedForAndDefaulted) {
  ParamsKeyRecorder recorder;
  Params p(nlohmann::json{{"a", 1}}, {"x.json", "/e"});
  p.has("b");
  p.quantity("c", Dimension::kLength, 1.0);
  EXPECT_EQ(recorder.keys().at("/e"), (std::set<std::string>{"b", "c"}));  // "a" was never asked for
}

TEST(SceneReference, TablesAreReadWithTheirHeadingsAndUnits) {
  const std::string file = ::testing::TempDir() + "/table.cpp";
  std::ofstream(file)
      << ("// widget: a thing\n// on two lines: with a colon.\n//\n"
          "// | key | type | default | meaning |\n// |---|---|---|---|\n"
          "// | size | [length, length] | 1 mm | how big |\n// | depth | depth | 1 D | where |\n"
          "//\n// gadget: another\n// | key | type | default | meaning |\n// |-|-|-|-|\n"
          "// | n | integer | 1 | how many |\n#include <x>\n// | not | a | table | row |\n");
  std::vector<KeyTable> t = ReadKeyTables(file);
  ASSERT_EQ(t.size(), 2u);
  EXPECT_EQ(t[0].section, "widget");
  EXPECT_EQ(t[0].prose, "a thing on two lines: with a colon.");
  EXPECT_EQ(t[0].keys(), (std::vector<std::string>{"size", "depth"}));
  EXPECT_EQ(t[0].rows[1].default_value, "1 D");
  EXPECT_EQ(t[1].section, "gadget");
  EXPECT_EQ(t[1].keys(), std::vector<std::string>{"n"});
  EXPECT_EQ(UnitsOfType(t[0].rows[0].type), "m, cm, mm, um, nm; a bare number is m");
  EXPECT_EQ(UnitsOfType("depth"), "D, or a length (m, cm, mm, um, nm); a bare number is refused");
  EXPECT_EQ(UnitsOfType("integer"), "");
}

}  // namespace
}  // namespace layerlab
