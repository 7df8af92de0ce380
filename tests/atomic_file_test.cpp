// AtomicFile: a file is replaced whole or not at all, and nothing of an abandoned write stays behind.
#include "layerlab/framework/atomic_file.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace layerlab {
namespace {

namespace fs = std::filesystem;

std::string Read(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(AtomicFile, AnAbandonedWriteLeavesNoTemporaryFileAndTheEarlierFileWhole) {
  const fs::path dir = fs::temp_directory_path() / ("layerlab_atomic_file_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path path = dir / "result.json";
  std::ofstream(path) << "earlier";
  std::string temp;
  {
    AtomicFile file(path.string());
    temp = file.temp_path();
    std::ofstream(temp) << "half written";
    // No Commit(): the write failed here.
  }
  EXPECT_FALSE(fs::exists(temp)) << "the abandoned temporary file " << temp << " was left behind";
  EXPECT_EQ(Read(path), "earlier");
  {
    AtomicFile file(path.string());
    temp = file.temp_path();
    std::ofstream(temp) << "new";
    file.Commit();
  }
  EXPECT_FALSE(fs::exists(temp));
  EXPECT_EQ(Read(path), "new");
  fs::remove_all(dir);
}

}  // namespace
}  // namespace layerlab
