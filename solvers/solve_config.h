// The "solve" section of a scene file: which solver, with which options, on
// which target. The command line overrides any of it.
//
// The target is a light-field folder ("target") or a target scene file
// ("target_scene", docs/target-format.md, rendered with Embree), never both;
// paths are relative to the scene file's folder.
//
//   "solve": { "solver": "hybrid", "target": "../data/dice", "iterations": 30,
//              "sub_iterations": 3, "warm_start_iterations": 2, "time_budget": "60 s"?, "tolerance": 0,
//              "initial_value": 0.5, "seed": 1, "threads": 0,
//              "sampling": "nearest", "target_range": "clip", "objective": "lightfield" }
#pragma once

#include <array>
#include <string>

#include "layerlab/solvers/solver.h"
#include "layerlab/systems/display_system.h"
#include "layerlab/systems/projection.h"
#include "layerlab/systems/scene.h"

namespace layerlab {

struct SolveConfig {
  std::string solver;        // default: DefaultSolverFor(system)
  std::string target;        // light-field folder, resolved against the scene file's folder
  std::string target_scene;  // or a target scene (layerlab-target/1) to render, resolved likewise
  // Where the target scene is moved to (m, eye space; MoveTargetScene) before it is rendered or traced: a
  // binocular eye's own display sees a scene given in the pair's frame from its own axis (TargetSceneMove).
  std::array<double, 3> target_moved_m{};
  Sampling sampling = Sampling::kNearest;
  SolverOptions options;  // the solver's defaults, then the scene's values
};

// The solver a display's structure calls for (SolverRegistry::DefaultFor of
// the built-ins: one branch -> multiplicative, one layer per branch ->
// additive-trust-region, else hybrid).
std::string DefaultSolverFor(const DisplaySystem& system);

// Why `solver` cannot minimize `objective` ("the solver \"hybrid\" minimizes
// the light-field objective only; ..."), or "" when it can.
std::string ObjectiveRefusal(const std::string& solver, ObjectiveKind objective,
                             const SolverRegistry& registry = SolverRegistry::Builtins());

// A path written in the scene file, relative to the scene file's folder.
std::string ResolveAgainstScene(const Scene& scene, const std::string& path);

// Where a target scene given in the pair's frame lies in the display frame of `eye` (PairFrameInDisplayFrame
// for a binocular eye, else 0).
std::array<double, 3> TargetSceneMove(const EyeModel& eye);

// Reads scene.document["solve"] if present (strictly: unknown keys, and keys
// of options the chosen solver does not read, are errors).
SolveConfig ReadSolveConfig(const Scene& scene, const DisplaySystem& system,
                            const SolverRegistry& registry = SolverRegistry::Builtins());

}  // namespace layerlab
