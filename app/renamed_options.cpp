#include "layerlab/app/renamed_options.h"

#include <string>

#include <CLI/CLI.hpp>

#include "layerlab/app/exit_status.h"

namespace layerlab::app {

void AddRenamedOptions(CLI::App& app) {
  for (const RenamedOption& r : kRenamedOptions)
    for (CLI::App* cmd : app.get_subcommands({}))
      if (cmd->get_name() == r.command)
        cmd->add_option_function<std::string>(r.old_name,
                                              [r](const std::string&) {
                                                throw UsageError(std::string(r.command) + ": " + r.old_name +
                                                                 " is now " + r.new_name + " (docs/cli.md)");
                                              })
            ->group("");
}

}  // namespace layerlab::app
