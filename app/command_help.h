// `layerlab help [COMMAND]`, and a first word that is no command: named as
// such, with the closest command, instead of CLI11's "A subcommand is
// required".
#pragma once

#include <optional>

namespace CLI {
class App;
}

namespace layerlab::app {

// The exit code when argv asks for help or names no command (the help or the error printed), else nullopt
// (parse as usual).
std::optional<int> HelpOrUnknownCommand(CLI::App& app, int argc, char** argv);

}  // namespace layerlab::app
