// Options renamed so that one name means one thing across the commands
// (docs/cli.md, "Renamed options"). The old name is still recognized, and
// refused naming the new one (exit 2), so that a script written for the old
// name fails with the fix instead of an "unknown option".
#pragma once

namespace CLI {
class App;
}

namespace layerlab::app {

struct RenamedOption {
  const char* command;
  const char* old_name;
  const char* new_name;
};

inline constexpr RenamedOption kRenamedOptions[] = {
    {"contrast", "--retina-resolution", "--resolution"},
    {"contrast", "--retina-field", "--field"},
    {"solve", "--initial", "--initial-value"},
    {"psf", "--spacing", "--resolution"},
    {"fit", "--reference", "--axis"},
    {"eyebox", "--range", "--eyebox-range"},
    {"eyebox", "--step", "--eyebox-step"},
};

// On each command the table names, its old names, hidden from help and from the catalogue.
void AddRenamedOptions(CLI::App& app);

}  // namespace layerlab::app
