// A pattern read from an OpenEXR file beside the scene: a panel's fixed
// pattern (a printed mask) or a backlight's emission image.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "layerlab/framework/params.h"

namespace layerlab {

struct PatternFile {
  std::string name;  // as the scene gives it
  std::string path;  // beside the scene file
  int64_t cols = 0, rows = 0;
  std::shared_ptr<const std::vector<float>> rgb;  // [row][col][rgb], each in [0, 1]
};

// The file named by `key`, relative to the scene file: channels R, G, B (or Y for all three), every value in
// [0, 1] (`what` names the range in messages: "transmittance", "emission"). Fails at `key` otherwise.
PatternFile ReadPatternFile(Params& p, const std::string& key, const std::string& what);

}  // namespace layerlab
