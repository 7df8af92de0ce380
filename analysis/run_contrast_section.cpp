// The run's contrast sweep (run.contrast, the paper's Fig. 5) of this
// display and the others it names, into OUT/contrast.
#include "layerlab/analysis/report_parts.h"
#include "layerlab/analysis/run_steps.h"

namespace layerlab {
namespace {

std::string RunContrastSweep(RunState& s) {
  ContrastOptions options = s.in.run.contrast.options;
  const std::optional<ContrastDisplay>& foreign = s.in.contrast_factorized_for;
  const size_t total =
      (s.in.contrast.size() + (foreign ? 1 : 0)) * options.frequencies_cpd.size() * options.target_diopters.size();
  options.show_progress = true;
  for (const std::string& w : ContrastWarnings(s.in.contrast, options)) s.page.warnings.push_back("contrast: " + w);
  s.outcome.contrast = RunContrast(s.in.contrast, options, foreign ? &*foreign : nullptr);
  AddContrastToPage(s.outcome.contrast, (s.out / "contrast").string(), "contrast/", &s.page);
  return "contrast sweep (" + std::to_string(total) + " solves)";
}

}  // namespace

RunSection ContrastRunSection() {
  return {"contrast", [](const RunInputs& in) { return in.run.contrast.enabled; }, RunContrastSweep};
}

}  // namespace layerlab
