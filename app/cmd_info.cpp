// layerlab info SCENE.json [--target LF_DIR] [--json] [--layout FILE.svg] [--patterns DIR]: the
// compiled display system, its optical paths, the light field it is bound to,
// the layer pixels rays reach, and for a time-multiplexed display whether its
// worst content, or a solve's patterns (--patterns), flicker visibly
// (analysis/flicker_check.h).
#include <iostream>
#include <memory>
#include <string>

#include "layerlab/analysis/flicker_check.h"
#include "layerlab/analysis/layout_svg.h"
#include "layerlab/app/commands.h"
#include "layerlab/framework/atomic_file.h"
#include "layerlab/framework/lightfield_io.h"
#include "layerlab/solvers/solution_writer.h"
#include "layerlab/systems/compile.h"
#include "layerlab/systems/system_report.h"

namespace layerlab::app {

void AddInfoCommand(CLI::App& app) {
  struct Options {
    std::string scene, target, layout, patterns;
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
  cmd->add_option("--patterns", options->patterns,
                  "A solve's folder: check its patterns for visible flicker (a time-multiplexed display; default: the "
                  "display's worst case)");
  cmd->callback([options] {
    DisplaySystem system = Compile(LoadScene(options->scene));
    LightFieldGeometry geometry =
        options->target.empty() ? DisplayLightFieldGeometry(system) : ReadLightFieldGeometry(options->target);
    DisplayModel model(system, geometry);
    if (!options->layout.empty()) WriteFileAtomically(options->layout, RenderLayoutSvg(system));
    std::vector<LayerCoverage> coverage = Coverage(model);
    const std::optional<FlickerVerdict> flicker = options->patterns.empty()
                                                      ? WorstCaseFlicker(system)
                                                      : CheckFlicker(model, ReadPatterns(model, options->patterns));
    if (options->json) {
      nlohmann::json j = SystemToJson(system);
      j.update(CoverageToJson(model, coverage));
      if (flicker) j["flicker"] = flicker->ToJson();
      std::cout << j.dump(2) << "\n";
    } else {
      std::cout << FormatSystemTable(system) << FormatCoverage(model, coverage);
      if (flicker) std::cout << flicker->Describe() << "\n";
    }
  });
}

}  // namespace layerlab::app
