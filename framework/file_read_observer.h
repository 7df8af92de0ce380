// Every input file the library reads for its content (scene files through
// ReadJsonFile, a target's files keyed for its render) is announced here, so
// that a test can count that a run reads each scene file once.
#pragma once

#include <functional>
#include <string>

namespace layerlab {

// Called by the readers with the path they open.
void AnnounceFileRead(const std::string& path);

// `read` is called with the path of every announced read from now on (nullptr: no longer).
void OnFileReadForTesting(std::function<void(const std::string& path)> read);

}  // namespace layerlab
