// Clearing what an earlier run left in an output folder, once the new run
// has written everything (so that a run that fails keeps the old results).
#pragma once

#include <set>
#include <string>

namespace layerlab {

// Removes every file under `folder` (recursively) whose absolute, lexically
// normal path is not in `keep`, then the folders left empty; returns the
// number of files removed. A missing folder removes nothing.
size_t RemoveFilesNotIn(const std::string& folder, const std::set<std::string>& keep);

}  // namespace layerlab
