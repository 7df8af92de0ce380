// layerlab info SCENE.json [--target LF_DIR] [--json] [--layout FILE.svg]: the
// compiled display system, its optical paths, the light field it is bound to,
// and the layer pixels rays reach.
#include <iostream>
#include <memory>
#include <string>

#include "layerlab/analysis/layout_svg.h"
#include "layerlab/app/commands.h"
#include "layerlab/framework/atomic_file.h"
#include "layerlab/framework/lightfield_io.h"
#include "layerlab/systems/compile.h"
#include "layerlab/systems/system_report.h"

namespace layerlab::app {

void AddInfoCommand(CLI::App& app) {
  struct Options {
    std::string scene, target, layout;
    bool json = false;
  };
  auto options = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand("info", "Compile a scene and print its optically equivalent system");
  cmd->add_option("scene", options->scene, "Scene file (JSON)")->required();
  cmd->add_option("--target", options->target,
                  "Light-field folder whose rays to bind the display to (default: the display's own frustum, "
                  "origin plane mid-range)");
  cmd->add_flag("--json", options->json, "Print the system as JSON for machines");
  cmd->add_option("--layout", options->layout, "Also write the side view of the unfolded optical path (SVG)");
  cmd->callback([options] {
    DisplaySystem system = Compile(LoadScene(options->scene));
    LightFieldGeometry geometry =
        options->target.empty() ? DisplayLightFieldGeometry(system) : ReadLightFieldGeometry(options->target);
    DisplayModel model(system, geometry);
    if (!options->layout.empty()) WriteFileAtomically(options->layout, RenderLayoutSvg(system));
    std::vector<LayerCoverage> coverage = Coverage(model);
    if (options->json) {
      nlohmann::json j = SystemToJson(system);
      j.update(CoverageToJson(model, coverage));
      std::cout << j.dump(2) << "\n";
    } else {
      std::cout << FormatSystemTable(system) << FormatCoverage(model, coverage);
    }
  });
}

}  // namespace layerlab::app
