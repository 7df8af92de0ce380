// --fovea and --jnd-exponent: how the perceptual metrics are measured
// (metrics/retinal_metrics.h, MetricSettings), shared by retina and compare.
#pragma once

#include <string>

#include "layerlab/metrics/retinal_metrics.h"

namespace CLI {
class App;
}

namespace layerlab::app {

struct MetricFlags {
  std::string fovea, jnd_exponent;
  bool given() const { return !fovea.empty() || !jnd_exponent.empty(); }
  // The flag a refusal of their being given names: "--fovea" or "--jnd-exponent".
  std::string named() const { return fovea.empty() ? "--jnd-exponent" : "--fovea"; }
};

void AddMetricSettingFlags(CLI::App* cmd, MetricFlags* flags);
// Throws layerlab::Error naming the flag for a bad value (an exponent below 1, a gaze not a pair of angles).
MetricSettings ParseMetricSettings(const MetricFlags& flags);

}  // namespace layerlab::app
