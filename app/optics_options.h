// What the eye and the panels do to light, set on the command line so that
// one set of scenes is seen through each model: --diffraction none, mtf or
// wave replaces the scene eye's "diffraction" (docs/eye-model.md),
// --fill-factor F or FX,FY every panel's "fill_factor" (the black matrix,
// whose grid diffracts the layers behind it: docs/optics.md, "Panel
// diffraction") and --response-time RISE[,FALL] every panel's liquid-crystal
// response (systems/lc_response.h).
#pragma once

#include <string>

#include <CLI/CLI.hpp>

#include "layerlab/systems/display_system.h"

namespace layerlab::app {

struct OpticsOptions {
  std::string diffraction, fill_factor, response_time;
};

void AddOpticsOptions(CLI::App* cmd, OpticsOptions& options);
// The panels' options alone, --fill-factor and --response-time (solve: the eye's diffraction does not enter a
// solve).
void AddPanelOptions(CLI::App* cmd, OpticsOptions& options);

// Applies the options given to `system` (compiled): a pinhole pupil with diffraction and a fill factor
// outside (0, 1] are refused, naming the option.
void ApplyOpticsOptions(const OpticsOptions& options, DisplaySystem* system);

}  // namespace layerlab::app
