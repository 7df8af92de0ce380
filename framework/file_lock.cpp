#include "layerlab/framework/file_lock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <cstring>
#include <utility>

#include "layerlab/framework/error.h"

namespace layerlab {
namespace {

std::function<void()> between_open_and_lock;  // BetweenOpenAndLockForTesting

// "1234 node7": what the holder writes into its lock file.
std::string HolderRecord() {
  char host[HOST_NAME_MAX + 1] = {};
  if (::gethostname(host, sizeof host - 1) != 0) host[0] = '\0';
  return std::to_string(::getpid()) + " " + host;
}

// The record a holder wrote, as words for a message; "" when it is not one.
std::string DescribeHolder(int fd) {
  char buf[HOST_NAME_MAX + 32] = {};
  const ssize_t n = ::pread(fd, buf, sizeof buf - 1, 0);
  const std::string text = n > 0 ? std::string(buf, static_cast<size_t>(n)) : "";
  const size_t space = text.find(' ');
  const std::string pid = text.substr(0, space);
  if (pid.empty() || pid.find_first_not_of("0123456789") != std::string::npos) return "";
  const std::string host = space == std::string::npos ? "" : text.substr(space + 1);
  const bool printable = host.find_first_of("\n\r\t") == std::string::npos;
  return "process " + pid + (host.empty() || !printable ? "" : " on host " + host);
}

}  // namespace

std::optional<FileLock> FileLock::TryLock(const std::string& path, std::string* holder) {
  int fd = -1;
  // A holder removes its lock file before it lets go (StagedOutput): a lock
  // taken on a file no longer at `path` locks nothing, so take the one there.
  for (int attempt = 0;; ++attempt) {
    fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0644);
    if (fd < 0) throw Error(path + ": cannot open the lock file: " + std::strerror(errno));
    if (between_open_and_lock) std::exchange(between_open_and_lock, nullptr)();
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
      const int e = errno;
      if (e != EWOULDBLOCK) {
        ::close(fd);
        throw Error(path + ": cannot lock: " + std::strerror(e));
      }
      if (holder) *holder = DescribeHolder(fd);
      ::close(fd);
      return std::nullopt;
    }
    struct stat held, now;
    if (::fstat(fd, &held) == 0 && ::stat(path.c_str(), &now) == 0 && held.st_dev == now.st_dev &&
        held.st_ino == now.st_ino)
      break;
    ::close(fd);
    if (attempt == 100) throw Error(path + ": cannot lock: the lock file keeps being replaced");
  }
  // Only the holder writes, so a reader of a held lock sees a whole record.
  const std::string record = HolderRecord();
  if (::ftruncate(fd, 0) != 0 || ::pwrite(fd, record.data(), record.size(), 0) != static_cast<ssize_t>(record.size())) {
    // The lock holds without the record; a second process is then not told which process holds it.
  }
  return FileLock(fd);
}

bool FileLock::HeldElsewhere(const std::string& path, std::string* holder) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NOFOLLOW | O_NONBLOCK);
  if (fd < 0) return false;
  const bool held = ::flock(fd, LOCK_SH | LOCK_NB) != 0 && errno == EWOULDBLOCK;
  if (held && holder) *holder = DescribeHolder(fd);
  ::close(fd);  // releases the shared lock taken to look
  return held;
}

void BetweenOpenAndLockForTesting(std::function<void()> meanwhile) { between_open_and_lock = std::move(meanwhile); }

FileLock& FileLock::operator=(FileLock&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = other.fd_;
    other.fd_ = -1;
  }
  return *this;
}

FileLock::~FileLock() {
  if (fd_ >= 0) ::close(fd_);  // closing the last descriptor releases the flock
}

}  // namespace layerlab
