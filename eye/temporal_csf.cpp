#include "layerlab/eye/temporal_csf.h"

#include <cmath>
#include <numbers>
#include <string>

#include "layerlab/framework/error.h"

namespace layerlab {
namespace {

constexpr double kK = 8.36831, kU0 = 2.44734, kTau10 = 0.0334009, kTau20 = 0.0477005, kT = 1.32776;
constexpr double kNasal = 0.171344, kN1 = 7, kN2 = 4, kIntegration = 0.1, kXMax0 = 12, kNMax = 15;
constexpr double kEta0 = 0.03, kPhi00 = 3e-8, kPhotons = 1.240e6;
constexpr double kGanglionFovea = 33163.2;  // cells / deg^2 (Watson 2014)
constexpr double kPi = std::numbers::pi;

// Watson's (2014) retinal ganglion cell density (cells / deg^2) on the nasal visual field's meridian, of the
// midget cells' independent mosaic (`midget`) or all cells', at eccentricity e.
double GanglionDensity(double e, bool midget) {
  constexpr double a = 0.9851, r2 = 1.058, re = 22.14, rm = 41.03;
  const double fraction = midget ? 0.8928 / 2 / (1 + e / rm) : 0.5;
  return kGanglionFovea * fraction * (a * std::pow(1 + e / r2, -2) + (1 - a) * std::exp(-e / re));
}

void Check(double value, bool zero_allowed, const char* name) {
  if (!std::isfinite(value) || !(zero_allowed ? value >= 0 : value > 0))
    throw Error(std::string("temporal CSF: ") + name + " " + std::to_string(value) + ": must be " +
                (zero_allowed ? "0 or more" : "above 0"));
}

}  // namespace

double TemporalContrastSensitivity(double w, const FlickerConditions& c) {
  Check(c.luminance_cd_m2, false, "luminance (cd/m2)");
  Check(c.area_deg2, false, "area (deg2)");
  Check(c.eccentricity_deg, true, "eccentricity (deg)");
  Check(w, true, "frequency (Hz)");
  const double e = c.eccentricity_deg, L = c.luminance_cd_m2;
  const double X0 = std::sqrt(c.area_deg2), sigma = std::sqrt(c.area_deg2 / kPi);
  const double u = (sigma < 2.5 ? 1.0 : 3.0) / (std::sqrt(kPi) * 2 * sigma);  // Barten's edge rule
  const double x_max = kXMax0 * std::pow(0.85 / (1 + std::pow(e / 4, 2)) + 0.15 / (1 + std::pow(e / 12, 2)), -0.5);
  const double eta = kEta0 * (0.4 / (1 + std::pow(e / 7, 2)) + 0.48 / (1 + std::pow(e / 20, 2)) + 0.12);
  const double phi0 = kPhi00 * (1 + kNasal * e);
  const double D = std::sqrt(4 / kPi * X0 * X0);
  const double d = 5 - 3 * std::tanh(0.4 * std::log10(L * X0 * X0 / (40.0 * 40.0)));
  const double E = kPi * d * d / 4 * L * (1 - std::pow(d / 9.7, 2) + std::pow(d / 12.4, 4));
  const double receptive_field = (kGanglionFovea / 2) / GanglionDensity(e, false);
  const double tau1 = kTau10 / (1 + 0.55 * std::log(1 + std::pow(1 + D, 0.6) * E / kT * receptive_field));
  const double tau2 = kTau20 / (1 + 0.37 * std::log(1 + std::pow(1 + D / 3.2, 5) * E / 120));
  const double h1 = std::pow(1 + std::pow(2 * kPi * w * tau1, 2), -kN1 / 2);
  const double h2 = std::pow(1 + std::pow(2 * kPi * w * tau2, 2), -kN2 / 2);
  const double f = 1 - std::sqrt(1 - std::exp(-(u / kU0) * (u / kU0)));
  const double lateral = std::max(h1 * (1 - h2 * f), 1e-300);
  const double photon_noise = 1 / (eta * kPhotons * E);
  const double half = 0.5 * X0;
  // The extents as that fit writes them (their parenthesization kept).
  const double X = std::pow(1 / (X0 * X0) + 1 / (x_max * x_max) +
                                ((half * half + 4 * e * e) / (half * half) + e * e) * u * u / (kNMax * kNMax),
                            -0.5);
  const double Y = std::pow(1 / (X0 * X0) + 1 / (x_max * x_max) + (1 + e * e) * u * u / (kNMax * kNMax), -0.5);
  return std::sqrt(2.0) / (2 * kK) * std::sqrt(X * Y * kIntegration / (photon_noise + phi0 / (lateral * lateral)));
}

double CriticalFlickerFrequency(const FlickerConditions& c, double modulation) {
  if (!std::isfinite(modulation) || !(modulation > 0))
    throw Error("temporal CSF: modulation " + std::to_string(modulation) + ": must be above 0");
  auto visible = [&](double w) { return modulation * TemporalContrastSensitivity(w, c) >= 1; };
  // S falls steeply above its peak (H1's n1 = 7): the last visible frequency on a 1 Hz scan to 500 Hz, refined.
  double last = -1;
  for (int w = 0; w <= 500; ++w)
    if (visible(w)) last = w;
  if (last < 0) return 0;
  double lo = last, hi = last + 1;
  while (hi - lo > 0.005) {
    const double mid = 0.5 * (lo + hi);
    (visible(mid) ? lo : hi) = mid;
  }
  return lo;
}

}  // namespace layerlab
