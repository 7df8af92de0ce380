#include "systems/optics.h"

#include <cmath>
#include <limits>
#include <numbers>

namespace layerlab {

FloatedImage FloatPanel(double s, double f, double e) {
  const double inf = std::numeric_limits<double>::infinity();
  double gap = f - s;  // 0 at the focal plane
  double denominator = s * f + e * gap;
  FloatedImage image;
  image.diopters = gap / denominator;
  image.tan_per_meter = f / denominator;
  if (gap > 0) {
    image.image_distance = s * f / gap;
    image.depth = image.image_distance + e;
    image.magnification = f / gap;
  } else {
    image.image_distance = image.depth = image.magnification = inf;
  }
  return image;
}

double PanelDistanceForDiopters(double diopters, double f, double e) {
  if (diopters == 0) return f;
  double d = 1.0 / diopters - e;
  return d * f / (d + f);
}

double FieldOfView(double tan_pitch, double pixels) { return 2.0 * std::atan(0.5 * pixels * tan_pitch); }

double NyquistCyclesPerDegree(double tan_pitch) {
  double pixel_degrees = std::atan(tan_pitch) * 180.0 / std::numbers::pi;
  return 1.0 / (2.0 * pixel_degrees);
}

}  // namespace layerlab
