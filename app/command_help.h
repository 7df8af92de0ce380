// `layerlab help [COMMAND]`, its machine-readable forms (--json: every command
// and option; --man; --completion bash|zsh), and a first word that is no
// command: named as such, with the closest command, instead of CLI11's "A
// subcommand is required".
#pragma once

#include <optional>

namespace CLI {
class App;
}

namespace layerlab::app {

// The `help` subcommand; add it after every other command.
void AddHelpCommand(CLI::App& app);

// Before parsing: when the first word that is not a global flag is no command, the error printed and the
// usage exit status; else nullopt (parse as usual).
std::optional<int> RefuseUnknownCommand(const CLI::App& app, int argc, char** argv);

}  // namespace layerlab::app
