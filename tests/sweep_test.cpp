// The sweep file (analysis/sweep_spec.h) and its expansion into jobs
// (analysis/sweep_jobs.h): bad files refused with file and JSON pointer, the
// grid's order, the values written at their pointers, paths rebased to the
// job's folder. Running the jobs is tested end to end in tests/cli/sweep_*.sh.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <set>

#include "layerlab/analysis/sweep_gather.h"
#include "layerlab/analysis/sweep_jobs.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/json_file.h"
#include "layerlab/framework/params.h"
#include "layerlab/systems/scene.h"
#include "layerlab/systems/scene_document.h"
#include "layerlab/tests/test_util.h"
#include "layerlab/tools/key_tables.h"

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
  for (const char* header : {"/analysis/sweep_spec.h", "/analysis/slurm_resources.h"})
    for (const KeyTable& table : ReadKeyTables(std::string(LAYERLAB_SOURCE_DIR) + header))
      for (const std::string& key : table.keys()) documented[table.section].insert(key);
  ASSERT_EQ(documented.size(), 3u);
  std::map<std::string, std::set<std::string>> read;
  nlohmann::json with_slurm = Base();
  with_slurm["slurm"] = {
      {"time", "1:00:00"}, {"mem", "4G"}, {"partition", "gpu"}, {"account", "a"}, {"cpus-per-task", 2}};
  for (const std::string& file : {testing::ExamplePath("sweeps/hybrid_small_24.json"), Write(with_slurm)}) {
    ParamsKeyRecorder recorder;
    ReadSweepSpec(file);
    for (const auto& [pointer, keys] : recorder.keys()) {
      const std::string section = pointer.empty()                         ? "sweep"
                                  : pointer.rfind("/parameters/", 0) == 0 ? "sweep.parameter"
                                  : pointer == "/slurm"                   ? "sweep.slurm"
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

// 64 parameters of 2 values: 2^64 points, which wrapped to 0 and slipped past the point limit.
TEST_F(SweepTest, AGridBeyondSixtyFourBitsIsRefusedNotWrapped) {
  nlohmann::json s = Base();
  s["parameters"] = nlohmann::json::array();
  for (int i = 0; i < 64; ++i)
    s["parameters"].push_back(
        {{"name", "p" + std::to_string(i)}, {"pointer", "/elements/0/pupil_diameter"}, {"values", {"3 mm", "5 mm"}}});
  EXPECT_NE(
      ErrorOf(s).find("sweep.json: /parameters: the grid's points: 9223372036854775808 x 2 does not fit in 64 bits"),
      std::string::npos)
      << ErrorOf(s);
  s["parameters"] = nlohmann::json(std::vector<nlohmann::json>(s["parameters"].begin(), s["parameters"].begin() + 17));
  EXPECT_NE(
      ErrorOf(s).find("sweep.json: /parameters: the grid has 131072 points; more than 100000 is surely a mistake"),
      std::string::npos)
      << ErrorOf(s);
}

TEST_F(SweepTest, SlurmResourcesAreReadInSlurmsFormsOnly) {
  nlohmann::json s = Base();
  s["slurm"] = {
      {"time", "1-12:30"}, {"mem", "4G"}, {"partition", "gpu,cpu"}, {"account", "proj_1"}, {"cpus-per-task", 8}};
  const SweepSpec spec = ReadSweepSpec(Write(s));
  EXPECT_EQ(spec.slurm.time, "1-12:30");
  EXPECT_EQ(spec.slurm.mem, "4G");
  EXPECT_EQ(spec.slurm.partition, "gpu,cpu");
  EXPECT_EQ(spec.slurm.account, "proj_1");
  EXPECT_EQ(spec.slurm.cpus_per_task, 8);
  SlurmResources over;
  over.time = "30";
  SlurmResources merged = spec.slurm;
  merged.Override(over);
  EXPECT_EQ(merged.time, "30");
  EXPECT_EQ(merged.mem, "4G");

  for (const char* t : {"10", "10:30", "1:00:00", "2-12", "2-12:30", "2-12:30:15", "UNLIMITED"})
    EXPECT_EQ(SlurmValueProblem("time", t), "") << t;
  for (const char* t : {"", "1h", "1:00:00:00", "-1", "1:00 ", "1\n#SBATCH --wrap=x", "$(x)"})
    EXPECT_NE(SlurmValueProblem("time", t), "") << t;
  for (const char* m : {"4096", "4G", "512M", "1T", "64k"}) EXPECT_EQ(SlurmValueProblem("mem", m), "") << m;
  for (const char* m : {"", "4 GB", "4GB", "-4G", "4G;x"}) EXPECT_NE(SlurmValueProblem("mem", m), "") << m;
  for (const char* p : {"gpu", "gpu,cpu", "a_b.c-d"}) EXPECT_EQ(SlurmValueProblem("partition", p), "") << p;
  for (const char* p : {"", "a b", "a,", "a\"b", "a#b", "HetJob", "x-packjob"})
    EXPECT_NE(SlurmValueProblem("partition", p), "") << p;
  EXPECT_NE(SlurmValueProblem("account", "a,b"), "");
  EXPECT_EQ(SlurmValueProblem("time", "1h"),
            "\"1h\" is not a Slurm time (minutes, minutes:seconds, hours:minutes:seconds, days-hours, "
            "days-hours:minutes, days-hours:minutes:seconds; e.g. \"2:00:00\" or \"1-12\")");
  for (const char* n : {"test sweep", "layer-spacing_2.0+pupil"}) EXPECT_EQ(SlurmJobNameProblem(n), "") << n;
  for (const char* n : {"", "a\nb", "$(touch x)", "`x`", "a;b", "a#b", "it's", "a\"b", "hetjob"})
    EXPECT_NE(SlurmJobNameProblem(n), "") << n;

  s["slurm"] = {{"mem", "4G; touch x"}};
  EXPECT_NE(ErrorOf(s).find("sweep.json: /slurm/mem: \"4G; touch x\" is not a Slurm memory size"), std::string::npos)
      << ErrorOf(s);
  s["slurm"] = {{"cpus-per-task", 0}};
  EXPECT_NE(ErrorOf(s).find("sweep.json: /slurm/cpus-per-task:"), std::string::npos) << ErrorOf(s);
  s["slurm"] = {{"nodes", 2}};
  EXPECT_NE(ErrorOf(s).find("sweep.json: /slurm/nodes:"), std::string::npos) << ErrorOf(s);
  s["slurm"] = "gpu";
  EXPECT_NE(ErrorOf(s).find("sweep.json: /slurm: must be an object"), std::string::npos) << ErrorOf(s);
}

// A label of 200000 digits (or spaces) is a label, not a number: it ended in a stack overflow (signal 11)
// in the regular expression that recognizes "<number> <unit>".
TEST_F(SweepTest, ALongLabelIsATextColumnNotAStackOverflow) {
  nlohmann::json s = Base();
  s["parameters"][0]["labels"] = {std::string(200000, '1'), " " + std::string(200000, ' ') + "1"};
  const SweepSpec spec = ReadSweepSpec(Write(s));
  EXPECT_EQ(spec.parameters[0].unit, "");
  EXPECT_EQ(spec.parameters[0].column(), "pupil");
}

// The base scene's target light field is an input too: an output folder inside it is refused before
// anything is written (the jobs would each have refused it after the folders were written into it).
TEST_F(SweepTest, AnOutputFolderInsideTheBaseScenesTargetIsRefusedUpFront) {
  ordered_json scene = ReadDocumentInOrder(testing::ExamplePath("small/hybrid_small.json"));
  scene["solve"] = {{"solver", "hybrid"}, {"target", "lf"}};
  scene.erase("run");
  std::ofstream(dir_ / "scene.json") << scene.dump(2);
  fs::create_directories(dir_ / "lf");
  nlohmann::json s = Base();
  s["scene"] = (dir_ / "scene.json").string();
  const SweepSpec spec = ReadSweepSpec(Write(s));
  const std::string out = (dir_ / "lf" / "sweep").string();
  try {
    LockSweepFolder(spec, out);
    ADD_FAILURE() << "an output folder inside the target light field was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("the base scene's /solve/target"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(out));
}

#if LAYERLAB_WITH_EMBREE
// The file's inode: two paths with the same one are one file, linked.
ino_t Inode(const fs::path& path) {
  struct stat st {};
  EXPECT_EQ(::stat(path.c_str(), &st), 0) << path;
  return st.st_ino;
}

// Issue 50: every job rendered the same target (10.7 s per job at paper scale). The first job keeps its
// render in DIR/targets/<key>/ and the next one, whose target scene is the same, links it instead.
TEST_F(SweepTest, JobsWithTheSameTargetRenderItOnce) {
  const SweepSpec spec = ReadSweepSpec(Write(Base()));
  const std::string out = (dir_ / "out").string();
  const std::vector<SweepJob> jobs = ExpandSweep(spec, out);
  WriteSweepFolders(spec, jobs, out);
  auto target = [&](size_t job) { return fs::path(JobFolder(out, jobs[job])) / "out" / "target"; };
  ASSERT_TRUE(RunSweepJob(spec, jobs[0], out, "local").complete);
  ASSERT_TRUE(RunSweepJob(spec, jobs[1], out, "local").complete);
  const nlohmann::json record = ReadJsonFile((target(0) / "render.json").string());
  const fs::path store = fs::path(out) / "targets" / record.at("digest").get<std::string>();
  ASSERT_TRUE(fs::exists(store / "render.json")) << "the first job's render is in the store";
  size_t files = 0;
  for (const auto& entry : fs::recursive_directory_iterator(store / "lightfield")) {
    if (!entry.is_regular_file()) continue;
    ++files;
    const fs::path relative = entry.path().lexically_relative(store);
    EXPECT_EQ(Inode(entry.path()), Inode(target(0) / relative)) << relative;
    EXPECT_EQ(Inode(entry.path()), Inode(target(1) / relative))
        << relative << ": the second job rendered the target again";
  }
  EXPECT_GT(files, 0u);
  // A render in the store that was changed since is not used: the next job renders and replaces it.
  fs::path some_file;
  for (const auto& entry : fs::recursive_directory_iterator(store / "lightfield"))
    if (entry.is_regular_file() && entry.path().extension() == ".exr") some_file = entry.path();
  ASSERT_FALSE(some_file.empty());
  const fs::path changed = some_file.string() + ".changed";
  fs::copy_file(some_file, changed);
  {
    std::fstream f(changed, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(-16, std::ios::end);
    f.write("0123456789abcdef", 16);
  }
  fs::rename(changed, some_file);  // a new file: the jobs' links keep the render they read
  ASSERT_TRUE(RunSweepJob(spec, jobs[2], out, "local").complete);
  const fs::path relative = some_file.lexically_relative(store);
  EXPECT_NE(Inode(target(2) / relative), Inode(target(1) / relative));
  EXPECT_EQ(Inode(some_file), Inode(target(2) / relative)) << "the new render replaced it";
}

// Issue 50: a peak accommodation is plotted against its grating's depth, the value a perfect display
// gives: job.json keeps it beside the result, and the plot draws it as a labelled band.
TEST_F(SweepTest, APeakAccommodationIsPlottedAgainstItsTargetDepth) {
  nlohmann::json sweep = Base();
  sweep["work"] = {"solve", "contrast"};
  sweep["parameters"][1]["values"] = {{0.5, 0.5}};
  sweep["parameters"][1]["labels"] = {"50/50"};
  const SweepSpec spec = ReadSweepSpec(Write(sweep));
  const std::string out = (dir_ / "out").string();
  const std::vector<SweepJob> jobs = ExpandSweep(spec, out);
  WriteSweepFolders(spec, jobs, out);
  for (const SweepJob& job : jobs) ASSERT_TRUE(RunSweepJob(spec, job, out, "local").complete);
  const nlohmann::json record = ReadJsonFile(JobFolder(out, jobs[0]) + "/job.json");
  std::map<std::string, double> ideal;
  for (const auto& r : record.at("results"))
    if (r.contains("ideal")) ideal[r.at("column")] = r.at("ideal");
  const std::map<std::string, double> expected = {{"peak accommodation, 0.7 D, 0.5 cpd (D)", 0.7},
                                                  {"peak accommodation, 1.9 D, 0.5 cpd (D)", 1.9}};
  EXPECT_EQ(ideal, expected) << record.dump();
  GatherSweep(spec, jobs, out);
  std::ifstream plot(out + "/plots/peak_accommodation_0_7_d_0_5_cpd_d.svg");
  const std::string svg((std::istreambuf_iterator<char>(plot)), std::istreambuf_iterator<char>());
  EXPECT_NE(svg.find(">target depth 0.7 D</text>"), std::string::npos) << svg;
}
#endif

}  // namespace
}  // namespace layerlab
