// What every benchmark runs on: the paper's prototype and its 2-layer
// baselines bound to the dice target (13 x 13 views of 400 x 200, RGB), or,
// in a smoke run or without ../shared/data, to a synthetic target of the
// same geometry (3 x 3 views of 40 x 20 for --smoke).
#pragma once

#include <memory>
#include <string>

#include "layerlab/framework/lightfield.h"
#include "layerlab/systems/display_model.h"

namespace layerlab::bench {

struct BenchSettings {
  bool smoke = false;  // reduced scale: seconds, for CI
};
BenchSettings& Settings();

struct Workload {
  DisplaySystem system;
  LightField target;
  std::unique_ptr<DisplayModel> model;
  std::string target_name;  // "dice" or "synthetic"
};

// "paper_prototype", "multiplicative_2layer" or "additive_2layer" from examples/; cached.
// With `subframes` > 1 the same scene shows that many subframes ("subframes": K).
const Workload& GetWorkload(const std::string& example, int subframes = 1);

// Peak resident memory of this process so far, MB.
double PeakRssMb();

}  // namespace layerlab::bench
