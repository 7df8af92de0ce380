// The main job of `layerlab run` (docs/run-section.md) as a library call, so
// that the command, a Python module and a C++ program run the same code:
// every input is read and checked first, then the steps the scene declares
// run in order, each long step with a progress line on stderr.
//
// The results are built in a staging folder inside the output folder
// (framework/staged_output.h) and switched into place only when every file
// is complete: a run that fails leaves the folder as it was, byte for byte.
#pragma once

#include <string>
#include <vector>

#include "layerlab/analysis/run_request.h"

namespace layerlab {

// Throws layerlab::Error (the output folder then as it was).
RunOutcome RunPipeline(const RunRequest& request);

// The files and folders a run owns in its output folder.
const std::vector<std::string>& RunOutputRoots();

}  // namespace layerlab
