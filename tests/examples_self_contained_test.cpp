// Issue 18: every shipped example works from the repository alone. Every
// path key of every JSON file under examples/ (scenes, target scenes,
// measurements) resolves, against its file's folder, to a file or folder
// that exists inside the repository; and the paths the readers themselves
// resolve (a scene's "solve" target and the "run" section's scenes, a target
// scene's meshes and images) do too.
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "layerlab/analysis/run_config.h"
#include "layerlab/framework/json_file.h"
#include "layerlab/solvers/solve_config.h"
#include "layerlab/systems/compile.h"
#include "layerlab/systems/display_model.h"
#include "layerlab/systems/scene.h"
#include "layerlab/targets/target_scene.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

namespace fs = std::filesystem;

const fs::path kRepository = fs::canonical(LAYERLAB_SOURCE_DIR);

// The keys whose string values (or arrays of strings) name files.
const std::set<std::string> kPathKeys = {"target", "target_scene", "display",     "file",
                                         "scenes", "scene",        "prescription"};

std::vector<fs::path> ExampleFiles() {
  std::vector<fs::path> files;
  for (const auto& entry : fs::recursive_directory_iterator(kRepository / "examples"))
    if (entry.is_regular_file() && entry.path().extension() == ".json") files.push_back(entry.path());
  return files;
}

// "" when `path` (relative to `folder` unless absolute) exists inside the repository, else why not.
std::string Outside(const fs::path& folder, const std::string& path) {
  const fs::path at = fs::path(path).is_absolute() ? fs::path(path) : folder / path;
  if (!fs::exists(at)) return path + " does not exist (" + at.lexically_normal().string() + ")";
  const fs::path real = fs::canonical(at);
  auto [r, p] = std::mismatch(kRepository.begin(), kRepository.end(), real.begin(), real.end());
  if (r != kRepository.end()) return path + " lies outside the repository (" + real.string() + ")";
  return "";
}

void CheckPathKeys(const nlohmann::json& value, const std::string& key, const fs::path& file, const std::string& at,
                   int* checked) {
  if (value.is_object()) {
    for (const auto& [k, v] : value.items()) CheckPathKeys(v, k, file, at + "/" + k, checked);
  } else if (value.is_array()) {
    for (size_t i = 0; i < value.size(); ++i) CheckPathKeys(value[i], key, file, at + "/" + std::to_string(i), checked);
  } else if (value.is_string() && kPathKeys.count(key)) {
    ++*checked;
    EXPECT_EQ(Outside(file.parent_path(), value.get<std::string>()), "") << file.string() << ": " << at;
  }
}

TEST(ExamplesSelfContainedTest, EveryPathKeyResolvesInsideTheRepository) {
  int checked = 0;
  const std::vector<fs::path> files = ExampleFiles();
  ASSERT_GT(files.size(), 10u);
  for (const fs::path& file : files) CheckPathKeys(ReadJsonFile(file.string()), "", file, "", &checked);
  EXPECT_GT(checked, 15) << "the walk found too few path keys to be looking at the examples";
}

TEST(ExamplesSelfContainedTest, WhatTheReadersResolveLiesInsideTheRepository) {
  int scenes = 0, targets = 0;
  for (const fs::path& file : ExampleFiles()) {
    const std::string format = ReadJsonFile(file.string()).value("format", "");
    if (format == "layerlab-scene/1") {
      ++scenes;
      const Scene scene = LoadScene(file.string());
      const DisplaySystem system = Compile(scene);
      const SolveConfig solve = ReadSolveConfig(scene, system);
      const RunConfig run = ReadRunConfig(scene, system);
      std::vector<std::string> paths = {solve.target, solve.target_scene};
      paths.insert(paths.end(), run.compare.scenes.begin(), run.compare.scenes.end());
      paths.insert(paths.end(), run.contrast.scenes.begin(), run.contrast.scenes.end());
      for (const std::string& p : paths) {
        if (p.empty()) continue;
        EXPECT_EQ(Outside(fs::current_path(), p), "") << file.string();
      }
    } else if (format == kTargetFormat) {
      ++targets;
      const TargetScene target = LoadTarget(file.string());
      for (const std::string& p : target.files_read) EXPECT_EQ(Outside(fs::current_path(), p), "") << file.string();
    }
  }
  EXPECT_GE(scenes, 10);
  EXPECT_GE(targets, 6);
}

// The main job's target is the shipped dice scene, at the paper's geometry:
// 13 x 13 views of 400 x 200 pixels.
TEST(ExamplesSelfContainedTest, TheMainJobRendersTheShippedDiceAtThePapersGeometry) {
  const Scene scene = LoadScene(testing::ExamplePath("paper_prototype.json"));
  const SolveConfig solve = ReadSolveConfig(scene, Compile(scene));
  EXPECT_EQ(solve.target, "");
  EXPECT_EQ(fs::canonical(solve.target_scene), fs::canonical(testing::ExamplePath("targets/dice.json")));
  const LightFieldGeometry g = LoadTarget(solve.target_scene).geometry;
  EXPECT_EQ(g.views_x, 13);
  EXPECT_EQ(g.views_y, 13);
  EXPECT_EQ(g.cols, 400);
  EXPECT_EQ(g.rows, 200);
  // The same field as the display's own light field (no resampling of the window).
  const LightFieldGeometry d = DisplayLightFieldGeometry(Compile(scene));
  EXPECT_TRUE(testing::Close(g.window_width_m / g.origin_z_m, d.window_width_m / d.origin_z_m, 1e-9));
  EXPECT_TRUE(testing::Close(g.window_height_m / g.origin_z_m, d.window_height_m / d.origin_z_m, 1e-9));
  EXPECT_EQ(g.eyebox_width_m, d.eyebox_width_m);
}

}  // namespace
}  // namespace layerlab
