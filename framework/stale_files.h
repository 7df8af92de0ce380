// Clearing what an earlier run left in an output folder, once the new run
// has written everything (so that a run that fails keeps the old results).
#pragma once

#include <set>
#include <string>
#include <vector>

namespace layerlab {

// Removes every file under `folder` (recursively) whose absolute, lexically
// normal path is not in `keep` and not under one of `keep_under`, then the
// folders left empty; returns the number of files removed. Symbolic links
// are removed as links, never followed; a missing folder, or one that is
// itself a symbolic link, removes nothing.
size_t RemoveFilesNotIn(const std::string& folder, const std::set<std::string>& keep,
                        const std::vector<std::string>& keep_under = {});

}  // namespace layerlab
