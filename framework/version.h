// The version of this build: CMake's project(VERSION ...) and, when the build
// knows it, the git commit it was built from (cmake/git_commit.cmake writes it
// at build time; only framework/version.cpp reads it, so a new commit
// recompiles that one file).
#pragma once

#include <string>

namespace layerlab {

std::string Version();    // "0.1.0"
std::string GitCommit();  // "037d768" (with "-dirty" for local changes), or "" when unknown
// "layerlab 0.1.0 (git 037d768)", or "layerlab 0.1.0" without a commit: for reports and --version.
std::string VersionLine();

}  // namespace layerlab
