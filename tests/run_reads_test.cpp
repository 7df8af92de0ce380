// `layerlab run` reads every scene file once (issue 41): the scene, the
// scenes it compares and contrasts, the target scene and the display the
// target's light field names, however many of them name the same file.
#include <filesystem>
#include <fstream>
#include <map>
#include <string>

#include <gtest/gtest.h>
#include <unistd.h>

#include "layerlab/analysis/run_pipeline.h"
#include "layerlab/framework/file_read_observer.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

namespace fs = std::filesystem;

TEST(RunReads, EverySceneFileOfTheMainJobIsReadOnce) {
#if !LAYERLAB_WITH_EMBREE
  GTEST_SKIP() << "the main job renders its target scene with Embree (LAYERLAB_WITH_EMBREE=OFF)";
#endif
  const fs::path out = fs::temp_directory_path() / ("layerlab_run_reads_" + std::to_string(::getpid()));
  fs::remove_all(out);
  std::map<std::string, int> reads;
  OnFileReadForTesting([&](const std::string& path) { ++reads[fs::weakly_canonical(path).string()]; });
  RunRequest request;
  request.scene = testing::ExamplePath("small/hybrid_small.json");
  request.out = out.string();
  request.iterations = 1;
  request.threads = 2;
  try {
    RunPipeline(request);
  } catch (...) {
    OnFileReadForTesting(nullptr);
    fs::remove_all(out);
    throw;
  }
  OnFileReadForTesting(nullptr);
  fs::remove_all(out);

  // The scene, the scene it compares with (examples/small/hybrid_pbs_hwp_small.json) and the
  // target scene, whose light field names the scene again ("display").
  for (const char* name :
       {"small/hybrid_small.json", "small/hybrid_pbs_hwp_small.json", "small/small_dice_target.json"}) {
    const std::string file = fs::weakly_canonical(testing::ExamplePath(name)).string();
    EXPECT_EQ(reads[file], 1) << file;
  }
  for (const auto& [file, count] : reads) EXPECT_EQ(count, 1) << file << " read " << count << " times";
}

// A run's contrast section whose window leaves the display's field, or whose
// factorized_for display has other layers, is refused at its key before
// anything is solved or written.
TEST(RunReads, ContrastDisplaysAreCheckedAtTheirKeysBeforeAnything) {
  const fs::path dir = fs::temp_directory_path() / ("layerlab_run_contrast_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  nlohmann::json scene = testing::ReadExample("small/hybrid_small.json");
  scene.erase("solve");
  auto refusal = [&](const nlohmann::json& contrast) -> std::string {
    scene["run"] = {{"contrast", contrast}};
    std::ofstream(dir / "scene.json") << scene.dump(1);
    RunRequest request;
    request.scene = (dir / "scene.json").string();
    request.out = (dir / "out").string();
    try {
      RunPipeline(request);
    } catch (const Error& e) {
      EXPECT_FALSE(fs::exists(dir / "out")) << e.what();
      return e.what();
    }
    return "";
  };
  const std::string window = refusal({{"field_center", "15 deg"}});
  EXPECT_NE(window.find("scene.json: /run/contrast/field_center: 15: the retinal window, 5.00 to 25.00 deg"),
            std::string::npos)
      << window;
  const std::string layers =
      refusal({{"factorized_for", testing::ExamplePath("multiplicative_2layer.json")}, {"retina_field", "4 deg"}});
  EXPECT_NE(layers.find("scene.json: /run/contrast/factorized_for: multiplicative_2layer: its patterns cannot be "
                        "shown on scene: 2 layers against 4"),
            std::string::npos)
      << layers;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace layerlab
