#include "layerlab/eye/chromatic_eye.h"

namespace layerlab {

double ThibosRefraction(double wavelength) {
  const double um = wavelength * 1e6;
  return 1.68524 - 0.63346 / (um - 0.21410);
}

double ThibosDefocus(double wavelength, double reference_wavelength) {
  return ThibosRefraction(reference_wavelength) - ThibosRefraction(wavelength);
}

}  // namespace layerlab
