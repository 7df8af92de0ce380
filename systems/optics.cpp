#include "layerlab/systems/optics.h"

#include <cmath>
#include <limits>
#include <numbers>

#include "layerlab/systems/ray_transfer.h"

namespace layerlab {
namespace {

RayTransfer<double> Magnifier(double f, double e) { return RayTransfer<double>().then_gap(e).then_power(1.0 / f); }

}  // namespace

FloatedImage FloatPanel(double s, double f, double e) {
  const double inf = std::numeric_limits<double>::infinity();
  RayTransfer<double> m = Magnifier(f, e).then_gap(s);
  if (ZeroWithinRounding(m.a, 1.0 + s / f)) m.a = 0;  // at the focal plane: a = 1 - s/f rounds to +-1e-16 for some f
  FloatedImage image;
  image.diopters = m.diopters();
  image.tan_per_meter = m.tan_per_meter();
  image.magnification = m.a > 0 ? m.magnification() : inf;
  image.image_distance_m = image.depth_m = inf;
  if (m.a > 0) {
    image.depth_m = 1.0 / image.diopters;
    image.image_distance_m = image.depth_m - e;
  }
  return image;
}

double PanelDistanceForDiopters(double diopters, double f, double e) {
  if (diopters == 0) return f;
  bool solvable = false;
  return GapForDiopters(Magnifier(f, e), diopters, &solvable);
}

double FieldOfView(double tan_pitch, double pixels) { return 2.0 * std::atan(0.5 * pixels * tan_pitch); }

double NyquistCyclesPerDegree(double tan_pitch) {
  double pixel_degrees = std::atan(tan_pitch) * 180.0 / std::numbers::pi;
  return 1.0 / (2.0 * pixel_degrees);
}

}  // namespace layerlab
