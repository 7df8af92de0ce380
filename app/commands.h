// The layerlab subcommands; each Add*Command registers its options and a
// callback on the top-level CLI11 app.
#pragma once

#include <CLI/CLI.hpp>

namespace layerlab::app {

void AddInfoCommand(CLI::App& app);

}  // namespace layerlab::app
