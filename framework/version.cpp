#include "layerlab/framework/version.h"

#include "layerlab/git_commit.h"  // generated at build time
#include "layerlab/version.h"     // generated at configure time

namespace layerlab {

std::string Version() { return LAYERLAB_VERSION; }

std::string GitCommit() { return LAYERLAB_GIT_COMMIT; }

std::string VersionLine() {
  const std::string commit = GitCommit();
  return "layerlab " + Version() + (commit.empty() ? "" : " (git " + commit + ")");
}

}  // namespace layerlab
