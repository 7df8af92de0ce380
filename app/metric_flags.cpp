#include "layerlab/app/metric_flags.h"

#include <CLI/CLI.hpp>

#include "layerlab/app/number_list.h"

namespace layerlab::app {

void AddMetricSettingFlags(CLI::App* cmd, MetricFlags* flags) {
  cmd->add_option("--fovea", flags->fovea,
                  "Weight every metric by eccentricity from this point, X,Y degrees right and up from the retina's "
                  "centre, where the eye looks (0,0): the cortical magnification's area (docs/metrics.md)");
  cmd->add_option("--jnd-exponent", flags->jnd_exponent,
                  "The JND metric's Minkowski pooling exponent, at least 1 (default 4; docs/metrics.md)");
}

MetricSettings ParseMetricSettings(const MetricFlags& flags) {
  MetricSettings s;
  if (!flags.fovea.empty()) s.fovea_deg = ParseSignedPair(flags.fovea, "--fovea", kDegrees);
  if (!flags.jnd_exponent.empty())
    s.jnd_minkowski_exponent = ParseOptionValue(flags.jnd_exponent, "--jnd-exponent", {Dimension::kFraction, ""});
  CheckMetricSettings(s, "--jnd-exponent", "--fovea");
  return s;
}

}  // namespace layerlab::app
