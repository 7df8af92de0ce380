// The sweep file (analysis/sweep_spec.h) and its expansion into jobs
// (analysis/sweep_jobs.h): bad files refused with file and JSON pointer, the
// grid's order, the values written at their pointers, paths rebased to the
// job's folder. Running the jobs is tested end to end in tests/cli/sweep_*.sh.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <set>

#include "analysis/sweep_jobs.h"
#include "framework/error.h"
#include "framework/json_file.h"
#include "framework/params.h"
#include "systems/scene.h"
#include "tests/test_util.h"
#include "tools/key_tables.h"

namespace layerlab {
namespace {

namespace fs = std::filesystem;
using nlohmann::ordered_json;

class SweepTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("layerlab_sweep_test_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // A sweep over examples/small/hybrid_small.json, written to the temporary folder.
  std::string Write(const nlohmann::json& sweep) {
    const std::string path = (dir_ / "sweep.json").string();
    std::ofstream(path) << sweep.dump(2);
    return path;
  }
  nlohmann::json Base() const {
    return {{"format", "layerlab-sweep/1"},
            {"scene", testing::ExamplePath("small/hybrid_small.json")},
            {"work", {"solve"}},
            {"parameters",
             {{{"name", "pupil"}, {"pointer", "/elements/0/pupil_diameter"}, {"values", {"3 mm", "5 mm"}}},
              {{"name", "combiner"},
               {"pointers", {"/elements/2/reflectance", "/elements/2/transmittance"}},
               {"values", {{0.5, 0.5}, {0.3, 0.7}, {0.7, 0.3}}},
               {"labels", {"50/50", "30/70", "70/30"}}}}}};
  }
  std::string ErrorOf(const nlohmann::json& sweep) {
    const std::string path = Write(sweep);
    try {
      ReadSweepSpec(path);
    } catch (const Error& e) {
      return e.what();
    }
    return "";
  }
  fs::path dir_;
};

TEST_F(SweepTest, GridInOrderWithTheValuesAtTheirPointers) {
  const SweepSpec spec = ReadSweepSpec(Write(Base()));
  ASSERT_EQ(spec.job_count(), 6u);
  const std::vector<SweepJob> jobs = ExpandSweep(spec, (dir_ / "out").string());
  ASSERT_EQ(jobs.size(), 6u);
  // The last parameter varies fastest: job 4 is pupil 5 mm (index 1), combiner 30/70 (index 1).
  EXPECT_EQ(jobs[4].id, "004");
  EXPECT_EQ(jobs[4].choice, (std::vector<size_t>{1, 1}));
  const ordered_json& scene = jobs[4].scene;
  EXPECT_EQ(scene["elements"][0]["pupil_diameter"], "5 mm");
  EXPECT_EQ(scene["elements"][2]["reflectance"], 0.3);
  EXPECT_EQ(scene["elements"][2]["transmittance"], 0.7);
  // Every other value as in the base scene; only the declared work remains in "run".
  const ordered_json base = jobs[0].scene;
  EXPECT_EQ(scene["elements"][3], base["elements"][3]);
  EXPECT_FALSE(scene.contains("run"));
  // The target scene, relative to the base scene's folder, is rebased to the job's folder.
  const fs::path job_folder = dir_ / "out" / "jobs" / "004";
  const fs::path target = job_folder / scene["solve"]["target_scene"].get<std::string>();
  EXPECT_EQ(target.lexically_normal(), fs::canonical(testing::ExamplePath("small/small_dice_target.json")));
}

TEST_F(SweepTest, LabelsWithOneUnitMakeANumericColumn) {
  nlohmann::json sweep = Base();
  sweep["parameters"][0]["values"] = {"3 mm", "4.5 mm"};
  const SweepSpec spec = ReadSweepSpec(Write(sweep));
  EXPECT_EQ(spec.parameters[0].column(), "pupil (mm)");
  EXPECT_EQ(spec.parameters[0].numbers, (std::vector<double>{3.0, 4.5}));
  EXPECT_EQ(spec.parameters[1].column(), "combiner");  // "50/50" is no quantity
  EXPECT_TRUE(spec.parameters[1].numbers.empty());
  sweep["parameters"][0]["values"] = {"3 mm", "0.4 cm"};  // two units: shown as written
  EXPECT_TRUE(ReadSweepSpec(Write(sweep)).parameters[0].numbers.empty());
}

TEST_F(SweepTest, WrittenScenesCompileAndRewritingKeepsUnchangedOnes) {
  const SweepSpec spec = ReadSweepSpec(Write(Base()));
  const std::string out = (dir_ / "out").string();
  const std::vector<SweepJob> jobs = ExpandSweep(spec, out);
  EXPECT_EQ(WriteSweepFolders(spec, jobs, out), 6u);
  for (const SweepJob& job : jobs) EXPECT_NO_THROW(LoadScene(JobFolder(out, job) + "/scene.json")) << job.id;
  EXPECT_EQ(WriteSweepFolders(spec, jobs, out), 0u);  // nothing changed: nothing written
  EXPECT_FALSE(ReadJobState(out, jobs[0]).complete);
}

TEST_F(SweepTest, BadFilesNameTheFileAndThePointer) {
  nlohmann::json s = Base();
  s["parameters"][0]["pointer"] = "/elements/0/pupil_diametr";
  EXPECT_NE(ErrorOf(s).find("sweep.json: /parameters/0/pointer: \"/elements/0/pupil_diametr\" is not in the scene"),
            std::string::npos)
      << ErrorOf(s);
  s = Base();
  s["parameters"][1]["pointers"][1] = "/elements/99/transmittance";
  EXPECT_NE(ErrorOf(s).find("/parameters/1/pointers/1: \"/elements/99/transmittance\" is not in the scene"),
            std::string::npos)
      << ErrorOf(s);
  s = Base();
  s["parameters"][0]["values"] = nlohmann::json::array();
  EXPECT_NE(ErrorOf(s).find("sweep.json: /parameters/0/values: is empty"), std::string::npos) << ErrorOf(s);
  s = Base();
  s["work"] = {"solve", "contrst"};
  EXPECT_NE(ErrorOf(s).find("sweep.json: /work/1: unknown work \"contrst\"; known: solve, retina, contrast (did you "
                            "mean \"contrast\"?)"),
            std::string::npos)
      << ErrorOf(s);
  s = Base();
  s["work"] = {"retina"};
  EXPECT_NE(ErrorOf(s).find("/work: \"retina\" looks at the solved patterns"), std::string::npos) << ErrorOf(s);
  s = Base();
  s["parameters"][1]["values"][2] = {0.7};
  EXPECT_NE(ErrorOf(s).find("/parameters/1/values/2: must be an array of 2 values"), std::string::npos) << ErrorOf(s);
  s = Base();
  s["parameters"][0]["value"] = {"3 mm"};
  EXPECT_NE(ErrorOf(s).find("/parameters/0"), std::string::npos) << ErrorOf(s);
  s = Base();
  s["parameters"][0]["values"] = {"3 mm", "3 mm"};
  EXPECT_NE(ErrorOf(s).find("/parameters/0/values/1: \"3 mm\" appears twice"), std::string::npos) << ErrorOf(s);
  s = Base();
  s["format"] = "layerlab-scene/1";
  EXPECT_NE(ErrorOf(s).find("sweep.json: /format"), std::string::npos) << ErrorOf(s);
}

// The key tables of analysis/sweep_spec.h (and so docs/sweeps.md) against the keys the reader asks for,
// over the shipped example and this test's sweep: no key undocumented, none documented and not read.
TEST_F(SweepTest, KeyTablesListWhatTheReaderReads) {
  std::map<std::string, std::set<std::string>> documented;
  for (const KeyTable& table : ReadKeyTables(std::string(LAYERLAB_SOURCE_DIR) + "/analysis/sweep_spec.h"))
    for (const std::string& key : table.keys()) documented[table.section].insert(key);
  ASSERT_EQ(documented.size(), 2u);
  std::map<std::string, std::set<std::string>> read;
  for (const std::string& file : {testing::ExamplePath("sweeps/hybrid_small_24.json"), Write(Base())}) {
    ParamsKeyRecorder recorder;
    ReadSweepSpec(file);
    for (const auto& [pointer, keys] : recorder.keys()) {
      const std::string section = pointer.empty()                         ? "sweep"
                                  : pointer.rfind("/parameters/", 0) == 0 ? "sweep.parameter"
                                                                          : pointer;
      read[section].insert(keys.begin(), keys.end());
    }
  }
  EXPECT_EQ(read, documented);
}

// manifest.json and job.json hold exactly the keys of their tables in analysis/sweep_jobs.h. A job with
// an unknown solver fails as it reads its inputs: recorded, not thrown.
TEST_F(SweepTest, RecordsHoldTheKeysTheirTablesList) {
  std::map<std::string, std::set<std::string>> documented;
  for (const KeyTable& table : ReadKeyTables(std::string(LAYERLAB_SOURCE_DIR) + "/analysis/sweep_jobs.h"))
    for (const std::string& key : table.keys()) documented[table.section].insert(key);
  nlohmann::json sweep = Base();
  sweep["parameters"][1] = {{"name", "solver"}, {"pointer", "/solve/solver"}, {"values", {"no-such-solver"}}};
  const SweepSpec spec = ReadSweepSpec(Write(sweep));
  const std::string out = (dir_ / "out").string();
  const std::vector<SweepJob> jobs = ExpandSweep(spec, out);
  WriteSweepFolders(spec, jobs, out);
  bool ran = false;
  const SweepJobState state = RunSweepJob(spec, jobs[0], out, "local", &ran);
  EXPECT_TRUE(ran);
  EXPECT_TRUE(state.failed);
  EXPECT_NE(state.error.find("no-such-solver"), std::string::npos) << state.error;
  auto keys = [](const std::string& path) {
    std::set<std::string> k;
    const nlohmann::json doc = ReadJsonFile(path);
    for (const auto& [key, value] : doc.items()) k.insert(key);
    return k;
  };
  EXPECT_EQ(keys(out + "/manifest.json"), documented["manifest.json"]);
  EXPECT_EQ(keys(JobFolder(out, jobs[0]) + "/job.json"), documented["job.json"]);
  // The failed job is not complete: the next run tries it again.
  EXPECT_FALSE(ReadJobState(out, jobs[0]).complete);
  EXPECT_TRUE(ReadJobState(out, jobs[0]).failed);
}

TEST_F(SweepTest, AnOutputFolderOverlappingAnInputIsRefused) {
  const SweepSpec spec = ReadSweepSpec(Write(Base()));
  const std::vector<SweepJob> jobs = ExpandSweep(spec, dir_.string());
  EXPECT_THROW(WriteSweepFolders(spec, jobs, dir_.string()), Error);  // the folder holding the sweep file
}

}  // namespace
}  // namespace layerlab
