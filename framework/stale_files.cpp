#include "framework/stale_files.h"

#include <filesystem>
#include <vector>

#include "framework/error.h"

namespace layerlab {

namespace fs = std::filesystem;

size_t RemoveFilesNotIn(const std::string& folder, const std::set<std::string>& keep) {
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) return 0;
  std::vector<fs::path> stale, folders;
  for (auto it = fs::recursive_directory_iterator(folder, ec); !ec && it != fs::recursive_directory_iterator();
       it.increment(ec)) {
    const fs::path p = fs::absolute(it->path()).lexically_normal();
    if (it->is_directory(ec))
      folders.push_back(p);
    else if (!keep.count(p.string()))
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
