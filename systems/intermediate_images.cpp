#include "layerlab/systems/intermediate_images.h"

#include <cmath>
#include <limits>

namespace layerlab {

std::vector<IntermediateImage> IntermediateImages(const VirtualLayer& layer) {
  std::vector<IntermediateImage> out;
  // The transfer from just in front of a powered element (eye side) to the panel:
  // grown from the panel backward, one element at a time.
  RayTransfer<double> to_panel;
  double from = layer.position_m;
  for (auto s = layer.path.rbegin(); s != layer.path.rend(); ++s) {
    if (!s->position_m) continue;
    RayTransfer<double> gap = RayTransfer<double>().then_gap(from - *s->position_m);
    to_panel = gap.then(to_panel);
    from = *s->position_m;
    if (s->power_diopters == 0) continue;
    to_panel = RayTransfer<double>().then_power(s->power_diopters).then(to_panel);
    // Rays leaving this plane at (y, u) reach the panel at a y + b u = a (y + (b/a) u):
    // the panel's image lies b/a beyond this element, magnified 1/a.
    IntermediateImage image;
    image.after = s->element;
    const double inf = std::numeric_limits<double>::infinity();
    if (ZeroWithinRounding(to_panel.a, std::abs(to_panel.a) + std::abs(to_panel.b * s->power_diopters))) {
      image.position_m = to_panel.b > 0 ? inf : -inf;
      image.magnification = to_panel.b > 0 ? inf : -inf;
    } else {
      const double beyond = to_panel.b / to_panel.a;
      image.position_m = *s->position_m + beyond;
      image.magnification = 1.0 / to_panel.a;
      image.real = beyond < 0;
    }
    out.push_back(image);
  }
  return out;
}

}  // namespace layerlab
