#include "layerlab/app/target_option.h"

#include "layerlab/framework/error.h"

namespace layerlab::app {

void AddTargetOptions(CLI::App* cmd, TargetOption& option, const std::string& what_for) {
  cmd->add_option("--target", option.target, "Target light-field folder" + what_for);
#if LAYERLAB_WITH_EMBREE
  cmd->add_option("--target-scene", option.target_scene,
                  "Or a target scene (JSON, docs/target-format.md), rendered with Embree" + what_for);
#endif
}

void ApplyTargetOption(const TargetOption& option, SolveConfig& config) {
  if (!option.target.empty() && !option.target_scene.empty()) throw Error("give --target or --target-scene, not both");
  if (!option.given()) return;
  config.target = option.target;
  config.target_scene = option.target_scene;
}

void RequireTarget(const SolveConfig& config, const std::string& scene_file) {
  if (config.target.empty() && config.target_scene.empty())
    throw Error(
        "no target: give --target LF_DIR or --target-scene TARGET.json, or \"solve\": {\"target\": ...} or "
        "{\"target_scene\": ...} in " +
        scene_file);
}

}  // namespace layerlab::app
