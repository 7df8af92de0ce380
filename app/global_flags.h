// The options every command takes, before or after its name
// ("layerlab -q solve ..." or "layerlab solve ... -q"): how much is said on
// stderr (-q/--quiet, -v/--verbose) and whether the result on stdout is JSON
// (--json).
#pragma once

#include <string>

namespace CLI {
class App;
}

namespace layerlab::app {

// On the top-level app and on each of its subcommands (add them first).
void AddGlobalFlags(CLI::App& app);

// Whether `arg` is one of the global flags (`layerlab -q info` still names its command second).
bool IsGlobalFlag(const std::string& arg);

// --json was given: the command prints its result as one JSON object (app/command_result.h).
bool JsonRequested();

}  // namespace layerlab::app
