#include "layerlab/app/pose_option.h"

#include <cmath>

#include "layerlab/app/number_list.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/units.h"
#include "layerlab/systems/eye_pose_limits.h"

namespace layerlab::app {

void AddPoseOptions(CLI::App* cmd, PoseOption& option) {
  cmd->add_option("--pupil-offset", option.pupil_offset,
                  "The eye's move across the eye plane X,Y: mm, or with units (default: the scene eye's pupil_offset)");
  cmd->add_option(
      "--gaze", option.gaze,
      "Where the eye looks X,Y: degrees right, up (default: the scene eye's gaze); the pupil turns with it");
}

std::string ApplyPoseOption(const PoseOption& option, DisplaySystem* system) {
  EyePose& pose = system->eye.pose;
  if (system->eye.binocular && (!option.pupil_offset.empty() || !option.gaze.empty()))
    throw Error(std::string(option.gaze.empty() ? "--pupil-offset" : "--gaze") +
                ": the scene's eye is one of a binocular pair, placed and turned by its \"binocular\" fixation");
  if (!option.pupil_offset.empty()) {
    pose.pupil_offset_m = ParseSignedPair(option.pupil_offset, "--pupil-offset", kMillimeters);
    for (double& v : pose.pupil_offset_m) {
      if (std::abs(v) > kMaxPupilOffset * 1e3)
        throw Error("--pupil-offset: \"" + option.pupil_offset + "\" reaches beyond " +
                    FormatFixed(kMaxPupilOffset * 1e3, 0) + " mm");
      v *= 1e-3;
    }
  }
  if (!option.gaze.empty()) {
    pose.gaze_rad = ParseSignedPair(option.gaze, "--gaze", kDegrees);
    for (double& v : pose.gaze_rad) {
      if (std::abs(v) > kMaxGaze * kDegreesPerRadian)
        throw Error("--gaze: \"" + option.gaze + "\" turns beyond " + FormatFixed(kMaxGaze * kDegreesPerRadian, 0) +
                    " deg");
      v *= kRadiansPerDegree;
    }
  }
  if (const std::string beyond = GazeBeyondField(*system, pose); !beyond.empty()) throw Error("--gaze: " + beyond);
  return PupilBeyondEyeboxWarning(system->eye);
}

std::string EyeboxGridWarning(const std::vector<PupilWeight>& pupils, const EyeModel& eye) {
  for (const PupilWeight& p : pupils) {
    EyeModel moved = eye;
    moved.pose = WithPupilMoved(eye.pose, p.offset_x_m, p.offset_y_m);
    if (const std::string beyond = PupilBeyondEyeboxWarning(moved); !beyond.empty())
      return "the eyebox grid's pupil position (" + FormatFixed(moved.pose.pupil_offset_m[0] * 1e3, 2) + ", " +
             FormatFixed(moved.pose.pupil_offset_m[1] * 1e3, 2) + ") mm: " + beyond;
  }
  return "";
}

}  // namespace layerlab::app
