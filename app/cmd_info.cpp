// layerlab info SCENE.json [--target LF_DIR] [--json] [--layout FILE.svg] [--patterns DIR]: the
// compiled display system, its optical paths, the light field it is bound to,
// the layer pixels rays reach, and for a time-multiplexed display whether its
// worst content, or a solve's patterns (--patterns), flicker visibly
// (analysis/flicker_check.h).
#include <memory>
#include <string>

#include "layerlab/analysis/flicker_check.h"
#include "layerlab/analysis/layout_svg.h"
#include "layerlab/app/command_result.h"
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
  };
  auto options = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand("info", "Compile a scene and print its optically equivalent system");
  cmd->add_option("scene", options->scene, "Scene file (JSON)")->required();
  cmd->add_option("--target", options->target,
                  "Light-field folder whose rays to bind the display to (default: the display's own frustum, "
                  "origin plane mid-range)");
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
    CommandResult result("info");
    result.Text(FormatSystemTable(system) + FormatCoverage(model, coverage) +
                (flicker ? flicker->Describe() + "\n" : std::string()));
    nlohmann::json fields = SystemToJson(system);
    fields.update(CoverageToJson(model, coverage));
    for (const auto& [key, value] : fields.items()) result[key] = value;
    if (flicker) result["flicker"] = flicker->ToJson();
    result.Print();
  });
}

}  // namespace layerlab::app
