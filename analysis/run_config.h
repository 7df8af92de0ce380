// The "run" section of a scene file: what `layerlab run` does with the display
// beyond factorizing its target (the target and the solver stay in "solve").
// Every analysis is optional and nothing undeclared is computed. Keys, units,
// ranges and defaults are described once, in analysis/run_option_table.h
// (docs/scene-reference.md, docs/run-section.md).
//
//   "run": { "retina":   { "accommodation": ["0.4 D", "1.0 D"], "resolution": "0.05 deg",
//                          "focal_stack": { "from": "0 D", "to": "2.6 D", "step": "0.1 D" } },
//            "contrast": { "depths": ["0.7 D", "1.3 D"], "frequencies": ["2 cpd"] },
//            "compare":  { "scenes": ["hybrid_pbs_hwp.json"], "solvers": ["hybrid"] } }
#pragma once

#include "layerlab/analysis/run_options.h"
#include "layerlab/systems/display_system.h"
#include "layerlab/systems/scene.h"

namespace layerlab {

// Reads scene.document["run"] strictly (unknown keys are refused with the
// closest known one); `system` gives the defaults that depend on the display.
RunConfig ReadRunConfig(const Scene& scene, const DisplaySystem& system);

}  // namespace layerlab
