#include "layerlab/app/eye_diffraction_option.h"

#include "layerlab/framework/error.h"

namespace layerlab::app {

void AddEyeDiffractionOption(CLI::App* cmd, std::string& diffraction) {
  cmd->add_option("--diffraction", diffraction,
                  "The eye's diffraction, replacing the scene's: none, mtf (the MTF times the geometric image) or "
                  "wave (the pupil function)")
      ->check(CLI::IsMember({"none", "mtf", "wave"}));
}

void ApplyEyeDiffractionOption(const std::string& diffraction, DisplaySystem* system) {
  if (diffraction.empty()) return;
  EyeModel& eye = system->eye;
  eye.diffraction = diffraction == "wave"  ? EyeDiffraction::kPupilFunction
                    : diffraction == "mtf" ? EyeDiffraction::kPupilMtf
                                           : EyeDiffraction::kNone;
  if (eye.diffraction != EyeDiffraction::kNone && !(eye.pupil_diameter_m > 0))
    throw Error("--diffraction " + diffraction + ": the scene's eye has a pinhole pupil (pupil_diameter 0)");
  if (eye.diffraction != EyeDiffraction::kPupilFunction) eye.stiles_crawford_rho_per_mm2 = 0;
}

}  // namespace layerlab::app
