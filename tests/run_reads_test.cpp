// `layerlab run` reads every scene file once (issue 41): the scene, the
// scenes it compares and contrasts, the target scene and the display the
// target's light field names, however many of them name the same file.
#include <filesystem>
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

}  // namespace
}  // namespace layerlab
