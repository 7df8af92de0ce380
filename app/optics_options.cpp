#include "layerlab/app/optics_options.h"

#include "layerlab/app/number_list.h"
#include "layerlab/framework/error.h"

namespace layerlab::app {

void AddOpticsOptions(CLI::App* cmd, OpticsOptions& options) {
  cmd->add_option("--diffraction", options.diffraction,
                  "The eye's diffraction, replacing the scene's: none, mtf (the MTF times the geometric image) or "
                  "wave (the pupil function)")
      ->check(CLI::IsMember({"none", "mtf", "wave"}));
  AddFillFactorOption(cmd, options);
}

void AddFillFactorOption(CLI::App* cmd, OpticsOptions& options) {
  cmd->add_option("--fill-factor", options.fill_factor,
                  "Every panel's pixel aperture over its pitch, F or FX,FY in (0, 1], replacing the scenes': below 1 "
                  "the panels' grids diffract the layers behind them");
}

void ApplyOpticsOptions(const OpticsOptions& options, DisplaySystem* system) {
  if (!options.diffraction.empty()) {
    EyeModel& eye = system->eye;
    eye.diffraction = options.diffraction == "wave"  ? EyeDiffraction::kPupilFunction
                      : options.diffraction == "mtf" ? EyeDiffraction::kPupilMtf
                                                     : EyeDiffraction::kNone;
    if (eye.diffraction != EyeDiffraction::kNone && !(eye.pupil_diameter_m > 0))
      throw Error("--diffraction " + options.diffraction + ": the scene's eye has a pinhole pupil (pupil_diameter 0)");
    if (eye.diffraction != EyeDiffraction::kPupilFunction) eye.stiles_crawford_rho_per_mm2 = 0;
  }
  if (!options.fill_factor.empty()) {
    std::vector<double> fill = ParseNumberList(options.fill_factor, "--fill-factor", {Dimension::kFraction, ""});
    if (fill.size() == 1) fill.push_back(fill[0]);
    if (fill.size() != 2 || !(fill[0] > 0 && fill[0] <= 1) || !(fill[1] > 0 && fill[1] <= 1))
      throw Error("--fill-factor: \"" + options.fill_factor + "\" is not F or FX,FY in (0, 1]");
    for (VirtualLayer& layer : system->layers) layer.panel.fill_factor = {fill[0], fill[1]};
  }
}

}  // namespace layerlab::app
