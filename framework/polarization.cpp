#include "layerlab/framework/polarization.h"

#include <cmath>

namespace layerlab {

Jones LinearPolarization(double angle) { return {Complex(std::cos(angle), 0.0), Complex(std::sin(angle), 0.0)}; }

JonesMatrix Retarder(double delta, double axis) {
  // R(axis) diag(1, e^{i delta}) R(-axis): the fast axis keeps its phase.
  double c = std::cos(axis), s = std::sin(axis);
  Complex slow = std::polar(1.0, delta);
  return {c * c + s * s * slow, c * s * (1.0 - slow), c * s * (1.0 - slow), s * s + c * c * slow};
}

void ChannelLight::attenuate(double transmittance) {
  if (polarized) {
    double amplitude = std::sqrt(transmittance);
    field.x *= amplitude;
    field.y *= amplitude;
  } else {
    intensity *= transmittance;
  }
}

}  // namespace layerlab
