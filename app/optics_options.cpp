#include "layerlab/app/optics_options.h"

#include "layerlab/app/number_list.h"
#include "layerlab/framework/error.h"

namespace layerlab::app {

void AddOpticsOptions(CLI::App* cmd, OpticsOptions& options) {
  cmd->add_option("--diffraction", options.diffraction,
                  "The eye's diffraction, replacing the scene's: none, mtf (the MTF times the geometric image) or "
                  "wave (the pupil function)")
      ->check(CLI::IsMember({"none", "mtf", "wave"}));
  AddPanelOptions(cmd, options);
}

void AddPanelOptions(CLI::App* cmd, OpticsOptions& options) {
  cmd->add_option("--response-time", options.response_time,
                  "Every panel's liquid-crystal response, RISE or RISE,FALL (10 to 90 %; ms, or with units), "
                  "replacing the scenes': a time-multiplexed display shows the time average of its relaxing panels");
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
  if (!options.response_time.empty()) {
    std::vector<double> times = ParseNumberList(options.response_time, "--response-time", {Dimension::kTime, "ms"});
    if (times.size() == 1) times.push_back(times[0]);  // in ms
    if (times.size() != 2 || !(times[0] <= 1000) || !(times[1] <= 1000))
      throw Error("--response-time: \"" + options.response_time + "\" is not RISE or RISE,FALL in [0, 1000 ms]");
    for (VirtualLayer& layer : system->layers)
      layer.panel.rise_time_s = times[0] * 1e-3, layer.panel.fall_time_s = times[1] * 1e-3;
  }
}

}  // namespace layerlab::app
