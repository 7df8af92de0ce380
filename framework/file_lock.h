// An advisory lock on a file (flock), held for the lifetime of the object, so
// that two processes never work on the same output at once. The kernel drops
// it when the process ends, however it ends: a killed run leaves no stale lock.
// On a cluster's shared file system flock works where the NFS client maps it
// to POSIX locks (Linux NFSv4 does).
#pragma once

#include <functional>
#include <optional>
#include <string>

namespace layerlab {

class FileLock {
 public:
  // Takes the lock on `path` (created if missing) without waiting. Returns
  // nothing when another process holds it; then *holder (optional) names it
  // ("process 1234 on host node7") when it wrote itself there (a layerlab
  // process does), else "". The host matters on a shared file system, where
  // the holder's pid means nothing on this node.
  // Throws layerlab::Error naming the file when it cannot be opened.
  static std::optional<FileLock> TryLock(const std::string& path, std::string* holder = nullptr);
  // Whether some process holds the lock on `path` now; false when the file is
  // missing. Never creates the file, never waits. *holder as above.
  static bool HeldElsewhere(const std::string& path, std::string* holder = nullptr);

  FileLock(FileLock&& other) noexcept : fd_(other.fd_) { other.fd_ = -1; }
  FileLock& operator=(FileLock&& other) noexcept;
  FileLock(const FileLock&) = delete;
  FileLock& operator=(const FileLock&) = delete;
  ~FileLock();

 private:
  explicit FileLock(int fd) : fd_(fd) {}
  int fd_ = -1;
};

// Fault injection for tests: `meanwhile` runs once, inside the next TryLock,
// between its opening the lock file and locking it, where another process may
// remove that file and lock a new one at the path.
void BetweenOpenAndLockForTesting(std::function<void()> meanwhile);

}  // namespace layerlab
