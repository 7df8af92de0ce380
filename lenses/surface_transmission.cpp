#include "layerlab/lenses/surface_transmission.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>

namespace layerlab::lenses {
namespace {

using Complex = std::complex<double>;

// cos of the angle in a medium of index n for the invariant n1 sin_i; complex
// (evanescent) when the angle does not exist there. Either root serves: the
// characteristic matrix is even in it.
Complex CosIn(double n, double n1_sin_i) {
  const double s = n1_sin_i / n;
  return std::sqrt(Complex(1.0 - s * s, 0.0));
}

// |r|^2 for the incidence admittance eta1 on a film (eta_c, delta) over eta2.
double FilmReflectance(Complex eta1, Complex eta_c, Complex delta, Complex eta2) {
  const Complex i(0.0, 1.0);
  const Complex b = std::cos(delta) + i * std::sin(delta) / eta_c * eta2;
  const Complex c = i * eta_c * std::sin(delta) + std::cos(delta) * eta2;
  const Complex y = c / b;
  return std::norm((eta1 - y) / (eta1 + y));
}

}  // namespace

Reflectance UncoatedReflectance(double n1, double n2, double cos_i) {
  const double sin_i_squared = 1.0 - cos_i * cos_i;
  const double cos_t_squared = 1.0 - (n1 / n2) * (n1 / n2) * sin_i_squared;
  if (cos_t_squared < 0.0) return {1.0, 1.0};
  const double cos_t = std::sqrt(cos_t_squared);
  const double rs = (n1 * cos_i - n2 * cos_t) / (n1 * cos_i + n2 * cos_t);
  const double rp = (n2 * cos_i - n1 * cos_t) / (n2 * cos_i + n1 * cos_t);
  return {rs * rs, rp * rp};
}

Reflectance QuarterWaveReflectance(double n1, double n2, double cos_i, double film_index, double design_wavelength_m,
                                   double wavelength_m) {
  const double n1_sin_i = n1 * std::sqrt(std::max(0.0, 1.0 - cos_i * cos_i));
  if (n1_sin_i > n2) return {1.0, 1.0};
  const Complex cos_c = CosIn(film_index, n1_sin_i);
  const Complex cos_2 = CosIn(n2, n1_sin_i);
  const double thickness_m = design_wavelength_m / (4.0 * film_index);
  const Complex delta = 2.0 * std::numbers::pi * film_index * thickness_m * cos_c / wavelength_m;
  Reflectance r;
  r.s = FilmReflectance(n1 * cos_i, film_index * cos_c, delta, n2 * cos_2);
  r.p = FilmReflectance(n1 / cos_i, film_index / cos_c, delta, n2 / cos_2);
  return r;
}

double SurfaceTransmittance(const Coating& coating, double n1, double n2, double cos_i, double wavelength_m) {
  switch (coating.kind) {
    case Coating::Kind::kQuarterWave:
      return 1.0 - QuarterWaveReflectance(n1, n2, cos_i, coating.index, coating.design_wavelength_m, wavelength_m)
                       .Unpolarized();
    case Coating::Kind::kStatedReflectance:
      return 1.0 - coating.reflectance;
    case Coating::Kind::kUncoated:
      break;
  }
  return 1.0 - UncoatedReflectance(n1, n2, cos_i).Unpolarized();
}

}  // namespace layerlab::lenses
