#include "layerlab/framework/file_lock.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "layerlab/framework/error.h"

namespace layerlab {
namespace {

namespace fs = std::filesystem;

fs::path TempLockPath(const char* name) {
  const fs::path dir = fs::temp_directory_path() / ("layerlab_file_lock_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir / name;
}

// flock conflicts between open file descriptions, so a second TryLock in the
// same process stands for a second process.
std::string ThisHost() {
  char host[256] = {};
  ::gethostname(host, sizeof host - 1);
  return host;
}

TEST(FileLock, ASecondTakerIsRefusedAndToldTheHoldersPidAndHost) {
  const std::string path = TempLockPath("held.lock").string();
  std::optional<FileLock> first = FileLock::TryLock(path);
  ASSERT_TRUE(first.has_value());
  std::string holder = "unset";
  EXPECT_FALSE(FileLock::TryLock(path, &holder).has_value());
  EXPECT_EQ(holder, "process " + std::to_string(::getpid()) + " on host " + ThisHost());
  holder = "unset";
  EXPECT_TRUE(FileLock::HeldElsewhere(path, &holder));
  EXPECT_EQ(holder, "process " + std::to_string(::getpid()) + " on host " + ThisHost());
  first.reset();
  EXPECT_FALSE(FileLock::HeldElsewhere(path)) << "the lock is released with its holder";
  EXPECT_TRUE(FileLock::TryLock(path).has_value()) << "the lock is released with its holder";
}

TEST(FileLock, AMissingLockFileIsNotHeldAndNotCreatedByLooking) {
  const std::string path = TempLockPath("missing.lock").string();
  EXPECT_FALSE(FileLock::HeldElsewhere(path));
  EXPECT_FALSE(fs::exists(path));
}

TEST(FileLock, AHolderThatWroteNoPidIsNotNamed) {
  const std::string path = TempLockPath("nopid.lock").string();
  std::optional<FileLock> first = FileLock::TryLock(path);
  ASSERT_TRUE(first.has_value());
  std::ofstream(path, std::ios::trunc) << "not a pid";
  std::string holder = "unset";
  EXPECT_FALSE(FileLock::TryLock(path, &holder).has_value());
  EXPECT_EQ(holder, "");
}

TEST(FileLock, AMovedLockIsStillHeld) {
  const std::string path = TempLockPath("moved.lock").string();
  std::optional<FileLock> first = FileLock::TryLock(path);
  ASSERT_TRUE(first.has_value());
  FileLock moved = std::move(*first);
  first.reset();  // the moved-from object must not release it
  EXPECT_FALSE(FileLock::TryLock(path).has_value());
}

// Between a taker's open and its lock the holder may let go and remove the file, and another process lock a new
// one at the path: a lock taken on the unlinked file locks nothing, so the taker looks again and finds the new holder.
TEST(FileLock, ALockTakenOnAFileReplacedMeanwhileIsNotHeld) {
  const std::string path = TempLockPath("replaced.lock").string();
  std::optional<FileLock> other;
  BetweenOpenAndLockForTesting([&] {
    fs::remove(path);
    other = FileLock::TryLock(path);
  });
  std::string holder = "unset";
  EXPECT_FALSE(FileLock::TryLock(path, &holder).has_value()) << "two holders of the lock at " << path;
  ASSERT_TRUE(other.has_value());
  EXPECT_EQ(holder, "process " + std::to_string(::getpid()) + " on host " + ThisHost());
}

TEST(FileLock, AnUnopenableFileIsAnErrorNamingIt) {
  try {
    FileLock::TryLock("/nonexistent_folder_for_layerlab/x.lock");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent_folder_for_layerlab/x.lock: cannot open the lock file"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace layerlab
