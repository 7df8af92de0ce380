// What is at a path, checked before it is opened: a FIFO would block a
// reader forever, a device never ends, a looping link or an overlong name
// would surface as a file-system exception. Each is refused with the path
// and the reason (layerlab::Error). Nothing here opens the path.
#pragma once

#include <string>

namespace layerlab {

// A regular file, following symbolic links. `what` names it in messages ("view").
void RequireRegularFile(const std::string& path, const std::string& what = "file");
// A folder, following symbolic links.
void RequireFolder(const std::string& path, const std::string& what = "folder");
// `path`, with every symbolic link resolved, lies inside `folder`'s real path.
void RequireInsideFolder(const std::string& path, const std::string& folder, const std::string& what);

}  // namespace layerlab
