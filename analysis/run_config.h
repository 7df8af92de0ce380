// The "run" section of a scene file: what `layerlab run` does with the display
// beyond factorizing its target (the target and the solver stay in "solve").
// Every analysis is optional and nothing undeclared is computed. Keys, units
// and defaults: docs/run-section.md.
//
//   "run": { "retina":   { "accommodation": ["0.4 D", "1.0 D"], "resolution": "0.05 deg",
//                          "focal_stack": { "from": "0 D", "to": "2.6 D", "step": "0.1 D" } },
//            "contrast": { "depths": ["0.7 D", "1.3 D"], "frequencies": ["2 cpd"] },
//            "compare":  { "scenes": ["hybrid_pbs_hwp.json"], "solvers": ["hybrid"] } }
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "layerlab/analysis/contrast.h"
#include "layerlab/solvers/solver.h"
#include "layerlab/systems/display_system.h"
#include "layerlab/systems/scene.h"

namespace layerlab {

struct RetinaRunConfig {
  bool enabled = false;
  std::vector<double> accommodation;  // D; default: the depths of the display's layers
  std::vector<double> focal_stack;    // D, from..to by step; empty when not asked for
  double resolution = 0.05;           // deg per retinal sample
  double field_x = 0, field_y = 0;    // deg; 0: the display's field of view
  bool natural = true;                // natural viewing of the target too
  bool natural_traced = false;        // traced in the target scene rather than read from its light field
  // Every state, sorted, duplicates removed: the slider's positions.
  std::vector<double> states() const;
};

struct ContrastRunConfig {
  bool enabled = false;
  ContrastOptions options;          // accommodation sweep, depths, frequencies, retina
  std::vector<std::string> scenes;  // more displays in the sweep (resolved paths)
};

struct CompareRunConfig {
  bool enabled = false;
  std::vector<std::string> scenes;        // displays beside this one (resolved paths)
  std::vector<std::string> solvers;       // empty: each scene's own solver
  std::optional<int> iterations;          // unset: each run's own
  std::optional<double> time_budget;      // s; unset: each run's own
  std::vector<ObjectiveKind> objectives;  // empty: each run's own (CompareSelection::objectives)
};

struct RunConfig {
  RetinaRunConfig retina;
  ContrastRunConfig contrast;
  CompareRunConfig compare;
  bool write_lightfield = false;  // the synthesized light field of the solve
  bool declared = false;          // the scene has a "run" section
};

// Reads scene.document["run"] strictly (unknown keys are refused with the
// closest known one); `system` gives the defaults that depend on the display.
RunConfig ReadRunConfig(const Scene& scene, const DisplaySystem& system);

}  // namespace layerlab
