// layerlab info SCENE.json [--json]: the compiled display system.
#include <iostream>
#include <memory>
#include <string>

#include "app/commands.h"
#include "systems/compile.h"
#include "systems/system_report.h"

namespace layerlab::app {

void AddInfoCommand(CLI::App& app) {
  struct Options {
    std::string scene;
    bool json = false;
  };
  auto options = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand("info", "Compile a scene and print its optically equivalent system");
  cmd->add_option("scene", options->scene, "Scene file (JSON)")->required();
  cmd->add_flag("--json", options->json, "Print the system as JSON for machines");
  cmd->callback([options] {
    DisplaySystem system = Compile(LoadScene(options->scene));
    if (options->json)
      std::cout << SystemToJson(system).dump(2) << "\n";
    else
      std::cout << FormatSystemTable(system);
  });
}

}  // namespace layerlab::app
