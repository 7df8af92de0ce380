// The run's retinal images over accommodation (run.retina), of the main
// solve and of natural viewing of the target, into OUT/retina.
#include "layerlab/analysis/report_parts.h"
#include "layerlab/analysis/retina_sweep.h"
#include "layerlab/analysis/run_steps.h"
#include "layerlab/analysis/world_scene.h"
#include "layerlab/framework/progress.h"

namespace layerlab {
namespace {

std::string RunRetina(RunState& s) {
  const RetinaRunConfig& r = s.in.run.retina;
  const SceneRadiance natural =
      r.natural ? s.target->Natural(r.natural_traced ? Target::Viewing::kTraced : Target::Viewing::kLightField)
                : SceneRadiance{};
  RetinaSweepOptions sweep{r.states(),
                           r.resolution_deg,
                           r.field_x_deg,
                           r.field_y_deg,
                           s.request.keep_images,
                           r.metrics,
                           r.metric_settings,
                           r.exr_float ? ExrPixels::kFloat : ExrPixels::kHalf,
                           WorldSceneRadiance(s.solved.model->system())};
  Progress progress("retina", sweep.states_diopters.size());
  std::vector<RetinaStateResult> states =
      WriteRetinaSweep(*s.solved.model, s.solved.patterns, natural, sweep, (s.out / "retina").string(),
                       [&](size_t done, size_t, const RetinaStateResult& state) {
                         progress.Update(done, "accommodation states traced (" + state.name + ")");
                       });
  progress.Finish(std::to_string(states.size()) + " states");
  AddRetinaToPage(states, r.accommodation_diopters, bool(natural), s.solved.model->white_luminance(), "retina/",
                  &s.page);
  s.outcome.retina = std::move(states);
  return "retina (" + std::to_string(s.outcome.retina.size()) + " accommodation states)";
}

}  // namespace

RunSection RetinaRunSection() {
  return {"retina", [](const RunInputs& in) { return in.run.retina.enabled; }, RunRetina};
}

}  // namespace layerlab
