// The image of a panel that each lens or curved mirror on its path forms,
// from the panel toward the eye (Gaussian imaging, the image of the image),
// for `layerlab info` and the report's layout diagram.
#pragma once

#include <string>
#include <vector>

#include "layerlab/systems/display_system.h"

namespace layerlab {

struct IntermediateImage {
  std::string after;         // the element whose power formed it
  double position_m = 0;     // m of unfolded path length from the pupil (+-inf: at infinity)
  double magnification = 0;  // of the panel, accumulated so far (negative: inverted)
  bool real = false;         // the light converges to it: it lies on the eye's side of `after`
};

// Farthest from the eye first: the image after the lens nearest the panel, ...,
// the image after the lens nearest the eye (the layer's eye-space image).
std::vector<IntermediateImage> IntermediateImages(const VirtualLayer& layer);

}  // namespace layerlab
