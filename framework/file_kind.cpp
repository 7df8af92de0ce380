#include "layerlab/framework/file_kind.h"

#include <sys/stat.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

#include "layerlab/framework/error.h"

namespace layerlab {
namespace {

namespace fs = std::filesystem;

// stat() that names the reason it failed; returns the mode.
mode_t StatOrRefuse(const std::string& path, const std::string& what) {
  struct stat st;
  if (::stat(path.c_str(), &st) == 0) return st.st_mode;
  const int error = errno;
  struct stat link;
  if (error == ENOENT && ::lstat(path.c_str(), &link) == 0)
    throw Error(path + ": the " + what + " is a symbolic link to nothing (dangling)");
  if (error == ENOENT) throw Error(path + ": no such " + what);
  if (error == ELOOP) throw Error(path + ": the " + what + " is a symbolic link loop (too many levels of links)");
  if (error == ENAMETOOLONG) throw Error(path + ": the " + what + "'s name is longer than the file system allows");
  throw Error(path + ": cannot use the " + what + ": " + std::strerror(error));
}

std::string Kind(mode_t mode) {
  if (S_ISDIR(mode)) return "a folder";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISSOCK(mode)) return "a socket";
  if (S_ISCHR(mode) || S_ISBLK(mode)) return "a device";
  return "not a regular file";
}

}  // namespace

void RequireRegularFile(const std::string& path, const std::string& what) {
  const mode_t mode = StatOrRefuse(path, what);
  if (!S_ISREG(mode))
    throw Error(path + ": the " + what + " is " + Kind(mode) + ", not a regular file; it is not read");
}

void RequireFolder(const std::string& path, const std::string& what) {
  const mode_t mode = StatOrRefuse(path, what);
  if (!S_ISDIR(mode))
    throw Error(path + ": the " + what + " is " + (S_ISREG(mode) ? "a file" : Kind(mode)) + ", not a folder");
}

void RequireInsideFolder(const std::string& path, const std::string& folder, const std::string& what) {
  std::error_code ec;
  const fs::path real = fs::canonical(path, ec);
  if (ec) throw Error(path + ": cannot resolve the " + what + ": " + ec.message());
  const fs::path root = fs::canonical(folder, ec);
  if (ec) throw Error(folder + ": cannot resolve the folder: " + ec.message());
  auto r = root.begin(), p = real.begin();
  for (; r != root.end(); ++r, ++p)
    if (p == real.end() || *p != *r)
      throw Error(path + ": the " + what + " is a symbolic link to " + real.string() + ", outside " + folder +
                  "; links out of the folder are not followed");
}

}  // namespace layerlab
