#include "framework/stale_files.h"

#include <algorithm>
#include <filesystem>
#include <iterator>
#include <vector>

#include "framework/error.h"

namespace layerlab {

namespace fs = std::filesystem;

namespace {

fs::path Normal(const fs::path& p) { return fs::absolute(p).lexically_normal(); }

// True if `p` is `root` or inside it (both normal and absolute).
bool Under(const fs::path& p, const fs::path& root) {
  auto [r, q] = std::mismatch(root.begin(), root.end(), p.begin(), p.end());
  return r == root.end() || (std::next(r) == root.end() && r->empty());  // "dir/" ends in an empty element
}

}  // namespace

size_t RemoveFilesNotIn(const std::string& folder, const std::set<std::string>& keep,
                        const std::vector<std::string>& keep_under) {
  std::error_code ec;
  const fs::file_status status = fs::symlink_status(folder, ec);
  if (ec || !fs::is_directory(status)) return 0;  // missing, a file, or a link to elsewhere
  std::vector<fs::path> protected_roots;
  for (const std::string& k : keep_under) protected_roots.push_back(Normal(k));
  std::vector<fs::path> stale, folders;
  for (auto it = fs::recursive_directory_iterator(folder, ec); !ec && it != fs::recursive_directory_iterator();
       it.increment(ec)) {
    const fs::path p = Normal(it->path());
    std::error_code status_ec;  // a file gone meanwhile has no status: nothing to do for it
    const fs::file_status s = it->symlink_status(status_ec);
    if (status_ec) continue;
    if (fs::is_directory(s)) {
      folders.push_back(p);
      continue;
    }
    if (keep.count(p.string())) continue;
    if (std::any_of(protected_roots.begin(), protected_roots.end(), [&](const fs::path& r) { return Under(p, r); }))
      continue;
    stale.push_back(p);
  }
  if (ec) throw Error(folder + ": cannot list the folder: " + ec.message());
  for (const fs::path& p : stale)
    if (!fs::remove(p, ec) && ec) throw Error(p.string() + ": cannot remove a stale output: " + ec.message());
  // Deepest first, so that a folder emptied by its children's removal goes too.
  for (auto it = folders.rbegin(); it != folders.rend(); ++it)
    if (fs::is_empty(*it, ec) && !ec) fs::remove(*it, ec);
  return stale.size();
}

}  // namespace layerlab
