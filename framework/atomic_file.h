// Nothing half-written: every output goes to a temporary file in the same
// folder and is renamed into place only once it is complete. Durable: the
// file's data reach the disk (fsync) before the rename, and its folder after,
// so a write reported as done survives a power loss, not just a kill.
#pragma once

#include <set>
#include <string>

namespace layerlab {

class AtomicFile {
 public:
  // Picks a temporary name next to `path` (same folder, so rename is atomic).
  explicit AtomicFile(std::string path);
  ~AtomicFile();  // removes the temporary file unless committed
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  const std::string& temp_path() const { return temp_; }
  const std::string& path() const { return path_; }
  // Renames the temporary file to the final path; throws layerlab::Error.
  void Commit();

 private:
  std::string path_, temp_;
  bool committed_ = false;
};

// Every path this process has committed so far, absolute and lexically normal.
std::set<std::string> CommittedPaths();

// Writes `contents` to `path` atomically; throws layerlab::Error naming the file.
void WriteFileAtomically(const std::string& path, const std::string& contents);

// fsync of a file's data, and of a folder's entries (what renames and
// creations in it did); throws layerlab::Error naming the path.
void SyncFile(const std::string& path);
void SyncFolder(const std::string& path);

}  // namespace layerlab
