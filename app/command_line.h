// The command line this process was started with, as a shell would take it
// back ("layerlab solve s.json --time-budget '5 s'"), for the reports.
#pragma once

#include <string>

namespace layerlab::app {

void SetCommandLine(int argc, const char* const* argv);
const std::string& CommandLine();

}  // namespace layerlab::app
