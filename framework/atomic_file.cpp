#include "layerlab/framework/atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <mutex>

#include "layerlab/framework/error.h"

namespace layerlab {
namespace {

std::mutex committed_mutex;
std::set<std::string> committed;

std::string Normal(const std::string& path) {
  std::error_code ec;
  std::filesystem::path p = std::filesystem::absolute(path, ec);
  return (ec ? std::filesystem::path(path) : p).lexically_normal().string();
}

void Sync(const std::string& path, int flags, const char* what) {
  const int fd = ::open(path.c_str(), flags | O_CLOEXEC);
  if (fd < 0) throw Error(path + ": cannot open " + what + " to flush it to disk: " + std::strerror(errno));
  const int rc = ::fsync(fd);
  const int e = errno;
  ::close(fd);
  if (rc != 0 && e != EINVAL)  // EINVAL: a file system that has nothing to flush (tmpfs on some kernels)
    throw Error(path + ": cannot flush " + what + " to disk (fsync): " + std::strerror(e));
}

}  // namespace

void SyncFile(const std::string& path) { Sync(path, O_RDONLY, "the file"); }
void SyncFolder(const std::string& path) { Sync(path, O_RDONLY | O_DIRECTORY, "the folder"); }

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)) {
  static std::atomic<unsigned> counter{0};
  std::filesystem::path p(path_);
  temp_ = (p.parent_path() /
           ("." + p.filename().string() + ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter++)))
              .string();
}

AtomicFile::~AtomicFile() {
  if (!committed_) std::remove(temp_.c_str());
}

void AtomicFile::Commit() {
  SyncFile(temp_);
  if (std::rename(temp_.c_str(), path_.c_str()) != 0)
    throw Error(path_ + ": cannot move the finished file into place: " + std::strerror(errno));
  committed_ = true;
  const std::string parent = std::filesystem::path(path_).parent_path().string();
  SyncFolder(parent.empty() ? "." : parent);
  const std::string normal = Normal(path_);
  std::lock_guard<std::mutex> lock(committed_mutex);
  committed.insert(normal);
}

std::set<std::string> CommittedPaths() {
  std::lock_guard<std::mutex> lock(committed_mutex);
  return committed;
}

void WriteFileAtomically(const std::string& path, const std::string& contents) {
  AtomicFile file(path);
  {
    std::ofstream out(file.temp_path(), std::ios::binary);
    if (!out) throw Error(path + ": cannot open for writing: " + std::strerror(errno));
    out.write(contents.data(), static_cast<std::streamsize>(contents.size()));
    out.flush();
    if (!out) throw Error(path + ": write failed (disk full?): " + std::strerror(errno));
  }
  file.Commit();
}

}  // namespace layerlab
