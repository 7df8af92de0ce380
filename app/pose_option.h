// The eye's pose on the command line: --pupil-offset X,Y (mm) and --gaze X,Y
// (deg) replace the scene eye's pupil_offset and gaze (elements/eye_pose.h).
// One home for the commands that look through an eye.
#pragma once

#include <string>

#include <CLI/CLI.hpp>

#include "layerlab/systems/display_system.h"

namespace layerlab::app {

struct PoseOption {
  std::string pupil_offset, gaze;
};

void AddPoseOptions(CLI::App* cmd, PoseOption& option);

// Sets system->eye.pose from the options given. Refuses, naming the option,
// an offset beyond the scene's limit and a gaze outside the display's field;
// returns the warning for a pupil that leaves the eyebox ("" inside it:
// PupilBeyondEyeboxWarning, systems/eye_pose_limits.h).
std::string ApplyPoseOption(const PoseOption& option, DisplaySystem* system);

}  // namespace layerlab::app
