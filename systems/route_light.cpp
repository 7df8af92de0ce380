#include "layerlab/systems/route_light.h"

#include <algorithm>
#include <cmath>

#include "layerlab/lenses/sequential_trace.h"

namespace layerlab {

void ApplyLightStep(const LightStep& step, const std::array<double, 3>& wavelengths_m, Light& light) {
  switch (step.element->kind()) {
    case ElementKind::kCombiner:
      static_cast<const CombinerElement*>(step.element)->transfer(step.action, light);
      break;
    case ElementKind::kInlineOptic:
      static_cast<const InlineOpticElement*>(step.element)->transfer(light);
      break;
    case ElementKind::kMirror:
      static_cast<const MirrorElement*>(step.element)->transfer(light);
      break;
    case ElementKind::kLens:  // thin lenses are ideal
      if (auto lens = static_cast<const LensElement*>(step.element)->lens_system())
        for (int c = 0; c < 3; ++c) light[c].attenuate(lenses::AxialTransmittance(*lens, wavelengths_m[c]));
      break;
    default:
      break;
  }
}

double BrightestThrough(const std::vector<LightStep>& route, const std::array<double, 3>& wavelengths_m) {
  // The route's Jones matrix, column by column: the images of x- and y-polarized light.
  std::array<Light, 2> columns;
  for (int k = 0; k < 2; ++k)
    for (ChannelLight& channel : columns[k]) {
      channel.polarized = true;
      channel.field = k == 0 ? Jones{{1, 0}, {0, 0}} : Jones{{0, 0}, {1, 0}};
    }
  for (auto step = route.rbegin(); step != route.rend(); ++step)
    for (Light& light : columns) ApplyLightStep(*step, wavelengths_m, light);
  double brightest = 0;
  for (int c = 0; c < 3; ++c) {  // the largest eigenvalue of M^H M = [[p, q], [q*, r]]
    const Jones& u = columns[0][c].field;
    const Jones& v = columns[1][c].field;
    const double p = u.intensity(), r = v.intensity();
    const double q = std::abs(std::conj(u.x) * v.x + std::conj(u.y) * v.y);
    brightest = std::max(brightest, 0.5 * (p + r) + std::sqrt(0.25 * (p - r) * (p - r) + q * q));
  }
  return brightest;
}

}  // namespace layerlab
