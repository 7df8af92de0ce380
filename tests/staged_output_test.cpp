#include "layerlab/framework/staged_output.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>

#include "layerlab/framework/atomic_file.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/file_lock.h"

namespace layerlab {
namespace {

namespace fs = std::filesystem;

std::string Read(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Every entry under `root` (hidden ones too), with a file's contents or a link's target.
std::map<std::string, std::string> Snapshot(const fs::path& root) {
  std::map<std::string, std::string> out;
  for (auto it = fs::recursive_directory_iterator(root); it != fs::recursive_directory_iterator(); ++it) {
    const std::string rel = it->path().lexically_relative(root).string();
    if (it->is_symlink())
      out[rel] = "link -> " + fs::read_symlink(it->path()).string();
    else if (it->is_directory())
      out[rel] = "folder";
    else
      out[rel] = Read(it->path());
  }
  return out;
}

void Write(const fs::path& p, const std::string& text) {
  fs::create_directories(p.parent_path());
  std::ofstream(p, std::ios::binary) << text;
}

long DeadPid() {
  const pid_t child = fork();
  if (child == 0) _exit(0);
  waitpid(child, nullptr, 0);
  return child;
}

class StagedOutputTest : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() / ("layerlab_staged_" + std::to_string(::getpid()) + "_" +
                                         ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(root_);
    fs::create_directories(root_);
  }
  void TearDown() override { fs::remove_all(root_); }
  // A first run: solve/a.txt, solve/old.txt, system.txt.
  void FirstRun() {
    StagedOutput s((root_ / "out").string(), "run", {"solve", "system.txt"}, {});
    Write(fs::path(s.staging()) / "solve" / "a.txt", "old a");
    Write(fs::path(s.staging()) / "solve" / "old.txt", "old only");
    WriteFileAtomically((fs::path(s.staging()) / "system.txt").string(), "old system");
    s.Commit();
  }
  fs::path root_;
};

TEST_F(StagedOutputTest, AFailedRunLeavesTheFolderByteForByteAsItWas) {
  FirstRun();
  Write(root_ / "out" / "notes.txt", "the user's");
  const auto before = Snapshot(root_ / "out");
  {
    StagedOutput s((root_ / "out").string(), "run", {"solve", "system.txt"}, {});
    Write(fs::path(s.staging()) / "solve" / "a.txt", "new a");
    Write(fs::path(s.staging()) / "system.txt", "new system");
    // No Commit(): the run failed here.
  }
  EXPECT_EQ(Snapshot(root_ / "out"), before);
  {  // an output folder this run created goes again
    StagedOutput s((root_ / "fresh").string(), "run", {"solve"}, {});
    Write(fs::path(s.staging()) / "solve" / "a.txt", "new a");
  }
  EXPECT_FALSE(fs::exists(root_ / "fresh"));
}

TEST_F(StagedOutputTest, TheSwitchOverRemovesOnlyWhatTheManifestRecords) {
  FirstRun();
  Write(root_ / "out" / "solve" / "user.txt", "the user's, not recorded");
  Write(root_ / "out" / "notes.txt", "the user's");
  StagedOutput s((root_ / "out").string(), "run", {"solve", "system.txt"}, {});
  Write(fs::path(s.staging()) / "solve" / "a.txt", "new a");
  Write(fs::path(s.staging()) / "solve" / "deep" / "b.txt", "new b");
  const StagedOutput::Switched done = s.Commit();
  EXPECT_EQ(done.written, (std::vector<std::string>{"solve/a.txt", "solve/deep/b.txt"}));
  EXPECT_EQ(done.removed, (std::vector<std::string>{"solve/old.txt", "system.txt"}));
  EXPECT_EQ(Read(root_ / "out" / "solve" / "a.txt"), "new a");
  EXPECT_EQ(Read(root_ / "out" / "solve" / "deep" / "b.txt"), "new b");
  EXPECT_FALSE(fs::exists(root_ / "out" / "solve" / "old.txt"));
  EXPECT_EQ(Read(root_ / "out" / "solve" / "user.txt"), "the user's, not recorded");
  EXPECT_EQ(Read(root_ / "out" / "notes.txt"), "the user's");
  for (const auto& entry : fs::directory_iterator(root_ / "out"))  // no staging folder, no journal
    EXPECT_EQ(entry.path().filename().string().find(".layerlab-staging"), std::string::npos) << entry.path();
  EXPECT_FALSE(fs::exists(root_ / "out" / ".layerlab-run-switch.json"));
}

TEST_F(StagedOutputTest, AnOutputThatIsContainsOrLiesInsideAnInputIsRefusedByRealPath) {
  Write(root_ / "x" / "lightfield" / "lightfield.json", "{}");
  fs::create_directory_symlink(root_ / "x" / "lightfield", root_ / "link");
  auto message = [&](const std::string& out, const std::string& input) {
    try {
      RefuseOutputOverlappingInputs(out, {{input, "the target"}});
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const std::string lf = (root_ / "x" / "lightfield").string();
  EXPECT_NE(message((root_ / "x").string(), lf).find("contains the target " + lf), std::string::npos);
  EXPECT_NE(message(lf, lf).find("is the target"), std::string::npos);
  EXPECT_NE(message(lf + "/views", lf).find("lies inside the target"), std::string::npos);
  EXPECT_NE(message((root_ / "x" / "y" / ".." / "lightfield").string(), (root_ / "link").string()).find("real paths"),
            std::string::npos);
  EXPECT_EQ(message((root_ / "x" / "other").string(), lf), "");
  // The command's roots are checked, and the folder itself: it may not hold an input, even one no root touches.
  EXPECT_THROW(
      StagedOutput((root_ / "x").string(), "solve", {"lightfield"}, {{(root_ / "link").string(), "the target"}}),
      Error);
  EXPECT_NE(message((root_ / "x").string(), lf).find("contains the target"), std::string::npos);
  try {
    StagedOutput((root_ / "x").string(), "contrast", {"contrast.csv"}, {{lf, "a scene"}});
    FAIL() << "an output folder that holds an input was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("the output contains a scene " + lf), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(root_ / "x" / ".layerlab-lock"));
  EXPECT_THROW(StagedOutput((root_ / "x" / "lightfield" / "out").string(), "solve", {"patterns"}, {{lf, "the target"}}),
               Error);
}

TEST_F(StagedOutputTest, TheSweepNeverRemovesAnInputNorGoesThroughALink) {
  FirstRun();
  // solve/ is now a link to a folder holding a file of the same name as a recorded one.
  Write(root_ / "elsewhere" / "old.txt", "precious");
  Write(root_ / "out" / "system.txt", "the user's own now");
  fs::rename(root_ / "out" / "solve", root_ / "solve_moved");
  fs::create_directory_symlink(root_ / "elsewhere", root_ / "out" / "solve");
  EXPECT_THROW(StagedOutput((root_ / "out").string(), "run", {"solve", "system.txt"}, {}), Error);  // not followed
  fs::remove(root_ / "out" / "solve");
  fs::rename(root_ / "solve_moved", root_ / "out" / "solve");
  // A recorded file that an input is now refused up front (the sweep would have removed it).
  EXPECT_THROW(StagedOutput((root_ / "out").string(), "run", {"solve", "system.txt"},
                            {{(root_ / "out" / "system.txt").string(), "the scene"}}),
               Error);
  // A recorded file replaced by a link to a file outside: the link goes, never what it points at.
  fs::remove(root_ / "out" / "solve" / "old.txt");
  fs::create_symlink(root_ / "elsewhere" / "old.txt", root_ / "out" / "solve" / "old.txt");
  StagedOutput s((root_ / "out").string(), "run", {"solve"}, {});
  Write(fs::path(s.staging()) / "solve" / "a.txt", "new a");
  EXPECT_EQ(s.Commit().removed, (std::vector<std::string>{"solve/old.txt"}));
  EXPECT_FALSE(fs::exists(fs::symlink_status(root_ / "out" / "solve" / "old.txt")));
  EXPECT_EQ(Read(root_ / "out" / "system.txt"), "the user's own now");  // recorded by run, but not under a root now
  EXPECT_EQ(Read(root_ / "elsewhere" / "old.txt"), "precious");
}

TEST_F(StagedOutputTest, SpecialFilesWhereOutputsGoAreRefusedBeforeAnythingIsWritten) {
  fs::create_directories(root_ / "out");
  ASSERT_EQ(mkfifo((root_ / "out" / "system.txt").c_str(), 0600), 0);
  try {
    StagedOutput s((root_ / "out").string(), "run", {"solve", "system.txt"}, {});
    FAIL() << "a FIFO was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("system.txt: is a FIFO where layerlab writes its output"), std::string::npos)
        << e.what();
  }
  fs::remove(root_ / "out" / "system.txt");
  fs::create_directories(root_ / "out" / "solve" / "a.txt");  // a folder where a file belongs
  const auto before = Snapshot(root_ / "out");
  StagedOutput s((root_ / "out").string(), "run", {"solve"}, {});
  Write(fs::path(s.staging()) / "solve" / "a.txt", "new");
  Write(fs::path(s.staging()) / "solve" / "b.txt", "new");
  EXPECT_THROW(s.Commit(), Error);
  Write(root_ / "not_a_folder", "x");
  EXPECT_THROW(StagedOutput((root_ / "not_a_folder").string(), "run", {"solve"}, {}), Error);
  EXPECT_EQ(Snapshot(root_ / "out").count("solve/b.txt"), 0u);
}

TEST_F(StagedOutputTest, WhatAKilledRunLeftIsClearedAndAnInterruptedSwitchOverFinished) {
  FirstRun();
  const long dead = DeadPid();
  const fs::path out = root_ / "out";
  // Killed while building: a staging folder and a temporary file of a process that is gone.
  Write(out / (".layerlab-staging-solve-" + std::to_string(dead)) / "lightfield" / "views" / "r00_c00.exr", "half");
  Write(out / "solve" / (".a.txt.tmp-" + std::to_string(dead) + "-3"), "half");
  Write(out / "solve" / (".a.txt.tmp-" + std::to_string(::getpid()) + "-999"), "a live process's");
  // Killed during a switch-over: solve/a.txt moved already, system.txt not yet, solve/old.txt not yet removed.
  const std::string staging = ".layerlab-staging-run-" + std::to_string(dead);
  Write(out / staging / "system.txt", "new system");
  Write(out / staging / ".layerlab-run-files.json",
        R"({"format":"layerlab-files/1","command":"run","files":["solve/a.txt","system.txt"]})");
  Write(out / "solve" / "a.txt", "new a");
  Write(out / ".layerlab-run-switch.json",
        R"({"format":"layerlab-switch/1","staging":")" + staging +
            R"(","move":["solve/a.txt","system.txt",".layerlab-run-files.json"],"remove":["solve/old.txt"]})");
  StagedOutput s(out.string(), "run", {"solve", "system.txt"}, {});
  EXPECT_EQ(s.recovered().size(), 3u);  // the switch-over, the dead staging folder, the dead temporary
  EXPECT_EQ(Read(out / "system.txt"), "new system");
  EXPECT_EQ(Read(out / "solve" / "a.txt"), "new a");
  EXPECT_FALSE(fs::exists(out / "solve" / "old.txt"));
  EXPECT_FALSE(fs::exists(out / staging));
  EXPECT_FALSE(fs::exists(out / ".layerlab-run-switch.json"));
  EXPECT_FALSE(fs::exists(out / (".layerlab-staging-solve-" + std::to_string(dead))));
  EXPECT_FALSE(fs::exists(out / "solve" / (".a.txt.tmp-" + std::to_string(dead) + "-3")));
  EXPECT_TRUE(fs::exists(out / "solve" / (".a.txt.tmp-" + std::to_string(::getpid()) + "-999")));
}

// An input named through a recorded output that is now a link to it: the folder holds no input by real path, so
// the run goes on, and the sweep keeps the link, the path by which the user named the input.
TEST_F(StagedOutputTest, TheSweepKeepsAStaleOutputThroughWhichAnInputIsNamed) {
  FirstRun();
  const fs::path out = root_ / "out";
  Write(root_ / "elsewhere" / "scene.json", "the scene");
  fs::remove(out / "solve" / "old.txt");
  fs::create_symlink(root_ / "elsewhere" / "scene.json", out / "solve" / "old.txt");
  StagedOutput s(out.string(), "run", {"solve"}, {{(out / "solve" / "old.txt").string(), "the scene"}});
  Write(fs::path(s.staging()) / "solve" / "a.txt", "new a");
  EXPECT_EQ(s.Commit().removed, std::vector<std::string>{});
  EXPECT_EQ(Read(out / "solve" / "old.txt"), "the scene");
  EXPECT_EQ(Read(root_ / "elsewhere" / "scene.json"), "the scene");
}

// A journal is data on disk (a damaged or crafted one): it moves nothing from or to outside its folder.
TEST_F(StagedOutputTest, AJournalThatWouldMoveAFileOutOfTheFolderIsRefused) {
  const fs::path out = root_ / "out";
  Write(out / "results.txt", "the user's");
  const std::string staging = ".layerlab-staging-run-" + std::to_string(DeadPid());
  fs::create_directories(out / staging);
  // Read through the staging folder "../results.txt" is out/results.txt; its place would be out/../results.txt.
  Write(out / ".layerlab-run-switch.json",
        R"({"format":"layerlab-switch/1","staging":")" + staging + R"(","move":["../results.txt"],"remove":[]})");
  try {
    StagedOutput s(out.string(), "run", {"solve"}, {});
    FAIL() << "a journal that moves a file out of its folder was carried out";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(".layerlab-run-switch.json: /move: \"../results.txt\" is not a path inside "
                                         "the folder"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(FinishPendingSwitchOvers((out / "results.txt").string()), Error);
  EXPECT_EQ(Read(out / "results.txt"), "the user's");
  EXPECT_FALSE(fs::exists(root_ / "results.txt"));
}

std::string ThisHost() {
  char host[256] = {};
  ::gethostname(host, sizeof host - 1);
  return host;
}

TEST_F(StagedOutputTest, ASecondWriterIsRefusedNamingTheFirstsPidAndHostAndTheLockGoesWithTheWriter) {
  const fs::path out = root_ / "out";
  std::optional<StagedOutput> first(std::in_place, out.string(), "solve", std::vector<std::string>{"patterns"},
                                    std::vector<NamedInput>{});
  Write(fs::path(first->staging()) / "patterns" / "a.txt", "first");
  // flock conflicts between open file descriptions: a second object in this process stands for a second process.
  try {
    StagedOutput second(out.string(), "retina", {"display"}, {});
    FAIL() << "a second writer into the same folder was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), out.string() + ": another layerlab process " + std::to_string(::getpid()) +
                                         " on host " + ThisHost() +
                                         " is writing into this folder; wait for it to end or give another "
                                         "output folder. Nothing was written");
  }
  EXPECT_TRUE(fs::exists(first->staging())) << "the refused writer touched the first one's work";
  first->Commit();
  first.reset();
  EXPECT_FALSE(fs::exists(out / ".layerlab-lock")) << "the lock file outlived its writer";
  StagedOutput third(out.string(), "retina", {"display"}, {});  // the folder is free again
  EXPECT_EQ(Read(out / "patterns" / "a.txt"), "first");
}

TEST_F(StagedOutputTest, WhatAProcessLeftIsClearedByTheLockNotByAPidThatLooksAlive) {
  const fs::path out = root_ / "out";
  // A staging folder and a temporary file named for pids that run now (init, this process: a reused pid, a
  // zombie, a process on another node of a shared file system all look alive), in a folder nobody holds.
  Write(out / ".layerlab-staging-solve-1" / "patterns" / "a.exr", "half");
  Write(out / (".layerlab-staging-run-" + std::to_string(::getpid())) / "system.txt", "half");
  Write(out / (".system.txt.tmp-" + std::to_string(::getpid()) + "-7"), "half");
  // A folder below with its own live writer (held lock): what is there is its work, left alone.
  Write(out / "solve" / ".layerlab-staging-solve-1" / "x.txt", "at work");
  const std::optional<FileLock> other = FileLock::TryLock((out / "solve" / ".layerlab-lock").string());
  ASSERT_TRUE(other.has_value());
  StagedOutput s(out.string(), "run", {"solve", "system.txt"}, {});
  EXPECT_FALSE(fs::exists(out / ".layerlab-staging-solve-1"));
  EXPECT_FALSE(fs::exists(out / (".layerlab-staging-run-" + std::to_string(::getpid())) / "system.txt"));
  EXPECT_FALSE(fs::exists(out / (".system.txt.tmp-" + std::to_string(::getpid()) + "-7")));
  EXPECT_TRUE(fs::exists(out / "solve" / ".layerlab-staging-solve-1" / "x.txt"));
}

// A second run: solve/a.txt, solve/b.txt, system.txt (4 moves with its manifest, then the staging folder's removal).
void StageSecondRun(const StagedOutput& s) {
  Write(fs::path(s.staging()) / "solve" / "a.txt", "new a");
  Write(fs::path(s.staging()) / "solve" / "b.txt", "new b");
  Write(fs::path(s.staging()) / "system.txt", "new system");
}

// The child is killed inside its commit, after `steps` steps of its switch-over; returns its exit status.
int CommitAndDieAfterSteps(const fs::path& out, int steps) {
  const pid_t child = fork();
  if (child == 0) {
    try {
      StagedOutput s(out.string(), "run", {"solve", "system.txt"}, {});
      StageSecondRun(s);
      EndProcessAfterSwitchOverStepsForTesting(steps);
      s.Commit();
    } catch (...) {
      _exit(1);
    }
    _exit(0);
  }
  int status = 0;
  waitpid(child, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST_F(StagedOutputTest, AKillInsideTheCommitLeavesAJournalThatTheNextReaderFinishes) {
  const fs::path out = root_ / "out";
  for (int steps = 1; steps <= 5; ++steps) {  // 4 moves, then the staging folder's removal
    SCOPED_TRACE("killed after " + std::to_string(steps) + " steps");
    fs::remove_all(out);
    FirstRun();
    ASSERT_EQ(CommitAndDieAfterSteps(out, steps), 86);
    // The commit itself wrote the journal before its first rename, and removes it last: the mix is marked, and
    // no staging folder is left without the journal that clears it.
    ASSERT_TRUE(fs::exists(out / ".layerlab-run-switch.json"));
    EXPECT_EQ(Read(out / "solve" / "a.txt"), "new a");  // the first move was made
    // A reader of anything below finishes the switch-over: the folder is the new result, whole.
    const std::vector<std::string> done = FinishPendingSwitchOvers((out / "solve").string());
    ASSERT_EQ(done.size(), 1u);
    EXPECT_NE(done[0].find("a layerlab run was killed while switching its results into place"), std::string::npos);
    EXPECT_EQ(Read(out / "solve" / "b.txt"), "new b");
    EXPECT_EQ(Read(out / "system.txt"), "new system");
    EXPECT_FALSE(fs::exists(out / "solve" / "old.txt"));
    EXPECT_FALSE(fs::exists(out / ".layerlab-run-switch.json"));
    EXPECT_FALSE(fs::exists(out / ".layerlab-lock"));
    for (const auto& e : fs::directory_iterator(out))
      EXPECT_EQ(e.path().filename().string().rfind(".layerlab-staging-", 0), std::string::npos) << e.path();
    EXPECT_TRUE(FinishPendingSwitchOvers((out / "solve").string()).empty());
  }
}

// A commit that fails inside its switch-over (a rename refused) leaves its journal; the staging folder holds
// what the journal has still to move, so it stays when the object goes, and the next reader finishes the job.
TEST_F(StagedOutputTest, ASwitchOverThatFailsMidwayKeepsItsStagedFilesForTheNextReaderToFinish) {
  FirstRun();
  const fs::path out = root_ / "out";
  std::string staging;
  {
    StagedOutput s(out.string(), "run", {"solve", "system.txt"}, {});
    staging = s.staging();
    StageSecondRun(s);
    FailSwitchOverAfterStepsForTesting(1);  // solve/a.txt is in place, solve/b.txt and system.txt are not
    EXPECT_THROW(s.Commit(), Error);
  }
  ASSERT_TRUE(fs::exists(out / ".layerlab-run-switch.json"));
  EXPECT_EQ(Read(fs::path(staging) / "solve" / "b.txt"), "new b") << "a file the journal has still to move is gone";
  const std::vector<std::string> done = FinishPendingSwitchOvers(out.string());
  ASSERT_EQ(done.size(), 1u);
  EXPECT_EQ(Read(out / "solve" / "a.txt"), "new a");
  EXPECT_EQ(Read(out / "solve" / "b.txt"), "new b");
  EXPECT_EQ(Read(out / "system.txt"), "new system");
  EXPECT_FALSE(fs::exists(out / "solve" / "old.txt"));
  EXPECT_FALSE(fs::exists(staging));
  EXPECT_FALSE(fs::exists(out / ".layerlab-run-switch.json"));
}

TEST_F(StagedOutputTest, AReaderRefusesAFolderALiveProcessIsSwitchingOver) {
  FirstRun();
  const fs::path out = root_ / "out";
  ASSERT_EQ(CommitAndDieAfterSteps(out, 1), 86);
  const std::optional<FileLock> live = FileLock::TryLock((out / ".layerlab-lock").string());
  ASSERT_TRUE(live.has_value());
  try {
    FinishPendingSwitchOvers((out / "solve" / "a.txt").string());
    FAIL() << "a reader went on while a live process was switching the folder over";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), out.string() + ": layerlab process " + std::to_string(::getpid()) + " on host " +
                                         ThisHost() +
                                         " is switching its results into place; read them once it has ended");
  }
  EXPECT_TRUE(fs::exists(out / ".layerlab-run-switch.json")) << "the live process's journal was touched";
}

}  // namespace
}  // namespace layerlab
