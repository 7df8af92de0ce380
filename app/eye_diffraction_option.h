// The eye's diffraction on the command line: --diffraction none, mtf or wave
// replaces the scene eye's "diffraction" (elements/eye.cpp, docs/eye-model.md),
// so one set of scenes is seen through each eye model.
#pragma once

#include <string>

#include <CLI/CLI.hpp>

#include "layerlab/systems/display_system.h"

namespace layerlab::app {

void AddEyeDiffractionOption(CLI::App* cmd, std::string& diffraction);

// Sets system->eye.diffraction when `diffraction` is given; a pinhole pupil is refused, naming the option.
void ApplyEyeDiffractionOption(const std::string& diffraction, DisplaySystem* system);

}  // namespace layerlab::app
