#include "layerlab/elements/wavefront.h"

#include <cmath>
#include <cstdlib>

#include "layerlab/framework/error.h"

namespace layerlab {
namespace {

double Factorial(int k) {
  double f = 1;
  for (int i = 2; i <= k; ++i) f *= i;
  return f;
}

double Radial(int n, int m, double rho) {
  double sum = 0;
  for (int s = 0; s <= (n - m) / 2; ++s)
    sum += (s % 2 ? -1.0 : 1.0) * Factorial(n - s) /
           (Factorial(s) * Factorial((n + m) / 2 - s) * Factorial((n - m) / 2 - s)) * std::pow(rho, n - 2 * s);
  return sum;
}

}  // namespace

ZernikeOrder ZernikeOrderOf(int j) {
  if (j < 0 || j > kMaxZernikeIndex) throw Error("Zernike index " + std::to_string(j) + " is outside 0 to 27");
  int n = 0;
  while ((n + 1) * (n + 2) / 2 <= j) ++n;  // (n + 1)(n + 2) / 2 is the first index of order n + 1
  return {n, 2 * j - n * (n + 2)};
}

double Zernike(int j, double x, double y) {
  const ZernikeOrder o = ZernikeOrderOf(j);
  const int m = std::abs(o.m);
  const double rho = std::hypot(x, y), theta = std::atan2(y, x);
  const double norm = std::sqrt((m == 0 ? 1.0 : 2.0) * (o.n + 1));
  const double angular = o.m >= 0 ? std::cos(m * theta) : std::sin(m * theta);
  return norm * Radial(o.n, m, rho) * angular;
}

bool Wavefront::empty() const {
  for (double c : coefficients_m)
    if (c != 0) return false;
  return true;
}

double WavefrontAt(const Wavefront& w, double x, double y) {
  const double radius = 0.5 * w.pupil_diameter_m;
  double sum = 0;
  for (size_t j = 0; j < w.coefficients_m.size(); ++j)
    if (w.coefficients_m[j] != 0) sum += w.coefficients_m[j] * Zernike(int(j), x / radius, y / radius);
  return sum;
}

WavefrontSlope WavefrontSlopeAt(const Wavefront& w, double x, double y) {
  // Central differences of a polynomial of order at most 6: the error is
  // h^2 / 6 of its third derivative, below 1e-9 relative at h = 1e-5 R.
  const double h = 1e-5 * 0.5 * w.pupil_diameter_m;
  return {(WavefrontAt(w, x + h, y) - WavefrontAt(w, x - h, y)) / (2 * h),
          (WavefrontAt(w, x, y + h) - WavefrontAt(w, x, y - h)) / (2 * h)};
}

const Wavefront* PopulationWavefront(const std::string& name) {
  static const Wavefront kSalmonVanDePol = [] {
    Wavefront w;
    w.coefficients_m.assign(13, 0.0);
    w.coefficients_m[12] = 0.13e-6;
    w.pupil_diameter_m = 6e-3;
    w.source = "salmon_van_de_pol_2006";
    return w;
  }();
  if (name == kSalmonVanDePol.source) return &kSalmonVanDePol;
  return nullptr;
}

std::vector<std::string> PopulationWavefrontNames() { return {"salmon_van_de_pol_2006"}; }

}  // namespace layerlab
