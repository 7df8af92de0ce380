// The eye's pose on the command line: --pupil-offset X,Y (mm) and --gaze X,Y
// (deg) replace the scene eye's pupil_offset and gaze (elements/eye_pose.h).
// One home for the commands that look through an eye.
#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "layerlab/solvers/types.h"
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

// The warning for the first of an eyebox grid's pupil positions (relative to `eye`'s) that leaves the eyebox,
// naming it; "" when all stay inside.
std::string EyeboxGridWarning(const std::vector<PupilWeight>& pupils, const EyeModel& eye);

}  // namespace layerlab::app
