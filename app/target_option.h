// The target of a command: --target LF_DIR (a light-field folder) or
// --target-scene T.json (a target scene, rendered on the fly with Embree);
// either replaces the scene's "solve" target. One home for the options of
// solve, compare and retina.
#pragma once

#include <string>

#include <CLI/CLI.hpp>

#include "layerlab/solvers/solve_config.h"

namespace layerlab::app {

struct TargetOption {
  std::string target, target_scene;
  bool given() const { return !target.empty() || !target_scene.empty(); }
};

// Registers --target and --target-scene (the latter only with Embree) on `cmd`.
void AddTargetOptions(CLI::App* cmd, TargetOption& option, const std::string& what_for);

// Replaces config's target by the one given, if any; refuses both at once.
void ApplyTargetOption(const TargetOption& option, SolveConfig& config);

// Throws layerlab::Error naming the options when `config` has no target.
void RequireTarget(const SolveConfig& config, const std::string& scene_file);

}  // namespace layerlab::app
