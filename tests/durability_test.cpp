// Durability (docs/robustness.md): the order of flushes and renames that makes
// a result survive a power loss. A power cut cannot be staged in a test, so
// this binary replaces fsync and rename with shims that record what they were
// called on (by path) before calling the C library's; a shim can also make
// fsync fail. The binary is its own so that no other test runs with the shims.
#include <dlfcn.h>
#include <gtest/gtest.h>
#include <limits.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "layerlab/framework/atomic_file.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/staged_output.h"

namespace {

std::vector<std::string> events;  // "fsync PATH" or "rename FROM -> TO", in call order
bool recording = false;
std::string fail_fsync_of;  // fsync of a path that begins with this fails with EIO

std::string PathOfFd(int fd) {
  char target[PATH_MAX];
  const ssize_t n = ::readlink(("/proc/self/fd/" + std::to_string(fd)).c_str(), target, sizeof target - 1);
  return n < 0 ? "?" : std::string(target, size_t(n));
}

std::string Absolute(const char* path) { return std::filesystem::absolute(path).lexically_normal().string(); }

}  // namespace

extern "C" int fsync(int fd) {
  using Fsync = int (*)(int);
  static const Fsync real = reinterpret_cast<Fsync>(::dlsym(RTLD_NEXT, "fsync"));
  const std::string path = PathOfFd(fd);
  if (recording) events.push_back("fsync " + path);
  if (!fail_fsync_of.empty() && path.rfind(fail_fsync_of, 0) == 0) {
    errno = EIO;
    return -1;
  }
  return real(fd);
}

extern "C" int rename(const char* from, const char* to) {
  using Rename = int (*)(const char*, const char*);
  static const Rename real = reinterpret_cast<Rename>(::dlsym(RTLD_NEXT, "rename"));
  if (recording) events.push_back("rename " + Absolute(from) + " -> " + Absolute(to));
  return real(from, to);
}

namespace layerlab {
namespace {

namespace fs = std::filesystem;

class DurabilityTest : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() / ("layerlab_durability_" + std::to_string(::getpid()) + "_" +
                                         ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(root_);
    fs::create_directories(root_);
    root_ = fs::canonical(root_);  // the shims see resolved paths
    events.clear();
  }
  void TearDown() override {
    recording = false;
    fail_fsync_of.clear();
    fs::remove_all(root_);
  }
  static void Write(const fs::path& p, const std::string& text) {
    fs::create_directories(p.parent_path());
    std::ofstream(p) << text;
  }
  // The index of the first event for which `match` holds, or -1.
  template <class Match>
  static long First(Match match, size_t from = 0) {
    for (size_t k = from; k < events.size(); ++k)
      if (match(events[k])) return long(k);
    return -1;
  }
  static long Fsync(const fs::path& p, size_t from = 0) {
    return First([&](const std::string& e) { return e == "fsync " + p.string(); }, from);
  }
  static long RenameTo(const fs::path& p) {
    return First([&](const std::string& e) {
      return e.size() > p.string().size() + 4 && e.rfind("rename ", 0) == 0 &&
             e.compare(e.size() - p.string().size() - 4, std::string::npos, " -> " + p.string()) == 0;
    });
  }
  static std::string Events() {
    std::string s;
    for (const std::string& e : events) s += "  " + e + "\n";
    return s;
  }
  fs::path root_;
};

TEST_F(DurabilityTest, AnAtomicFileIsFlushedBeforeItsRenameAndItsFolderAfter) {
  const fs::path file = root_ / "result.json";
  recording = true;
  WriteFileAtomically(file.string(), "{}\n");
  recording = false;
  const long rename = RenameTo(file);
  ASSERT_GE(rename, 0) << Events();
  const std::string temp = events[size_t(rename)].substr(7, events[size_t(rename)].find(" -> ") - 7);
  const long flushed = Fsync(temp);
  EXPECT_GE(flushed, 0) << "the temporary file is never flushed:\n" << Events();
  EXPECT_LT(flushed, rename) << "the temporary file is flushed after the rename:\n" << Events();
  EXPECT_GT(Fsync(root_, size_t(rename)), rename) << "the folder is not flushed after the rename:\n" << Events();
}

TEST_F(DurabilityTest, AFailedFlushIsAnErrorAndNothingIsRenamedIntoPlace) {
  const fs::path file = root_ / "result.json";
  fail_fsync_of = (root_ / ".result.json.tmp-").string();  // the temporary file AtomicFile writes first
  recording = true;
  try {
    WriteFileAtomically(file.string(), "{}\n");
    ADD_FAILURE() << "a failed fsync was not reported:\n" << Events();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("cannot flush the file to disk (fsync)"), std::string::npos) << e.what();
  }
  recording = false;
  EXPECT_FALSE(fs::exists(file));
  EXPECT_EQ(RenameTo(file), -1) << Events();
}

TEST_F(DurabilityTest, ASwitchOverFlushesTheStagedFilesTheJournalAndEveryChangedFolderInOrder) {
  const fs::path out = root_ / "out";
  StagedOutput s(out.string(), "run", {"solve", "system.txt"}, {});
  const fs::path staging(s.staging());
  Write(staging / "solve" / "a.txt", "a");
  Write(staging / "solve" / "deep" / "b.txt", "b");
  Write(staging / "system.txt", "system");
  recording = true;
  s.Commit();
  recording = false;
  const fs::path journal = out / ".layerlab-run-switch.json";
  const long journal_in_place = RenameTo(journal);
  ASSERT_GE(journal_in_place, 0) << "the commit writes no journal:\n" << Events();
  // Every staged file, before the journal that will move it is trusted.
  for (const char* rel : {"solve/a.txt", "solve/deep/b.txt", "system.txt"}) {
    const long flushed = Fsync(staging / rel);
    EXPECT_GE(flushed, 0) << rel << " is never flushed:\n" << Events();
    EXPECT_LT(flushed, journal_in_place) << rel << " is flushed after the journal:\n" << Events();
  }
  // The journal's folder, after the journal and before the first move.
  const long first_move = RenameTo(out / "solve" / "a.txt");
  ASSERT_GT(first_move, journal_in_place) << Events();
  const long folder_flushed = Fsync(out, size_t(journal_in_place));
  EXPECT_GE(folder_flushed, 0) << Events();
  EXPECT_LT(folder_flushed, first_move) << "the journal's folder is not flushed before the first move:\n" << Events();
  // Every folder a move changed, after the last move.
  long last_move = std::max({first_move, RenameTo(out / "solve" / "deep" / "b.txt"), RenameTo(out / "system.txt")});
  for (const fs::path& changed : {out / "solve", out / "solve" / "deep", out})
    EXPECT_GT(Fsync(changed, size_t(last_move)), last_move) << changed << " is not flushed after the moves:\n"
                                                            << Events();
}

}  // namespace
}  // namespace layerlab
