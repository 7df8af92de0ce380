#include "layerlab/eye/barten_csf.h"

#include <cmath>
#include <numbers>
#include <string>

#include "layerlab/framework/error.h"

namespace layerlab {
namespace {

constexpr double kK = 3, kT = 0.1, kXMax = 12, kNMax = 15, kEta = 0.03, kP = 1.2274e6, kPhi0 = 3e-8, kU0 = 7;
constexpr double kSigma0Deg = 0.5 / 60, kCabDegPerMm = 0.08 / 60;

double AngularSize(double u, double field_deg) {
  return 1 / std::sqrt(1 / (field_deg * field_deg) + 1 / (kXMax * kXMax) + u * u / (kNMax * kNMax));
}

void CheckPositive(double value, const char* name) {
  if (!(value > 0) || !std::isfinite(value))
    throw Error(std::string("Barten CSF: ") + name + " " + std::to_string(value) + ": must be above 0");
}

}  // namespace

double BartenPupilDiameterMm(const BartenConditions& c) {
  return 5 - 3 * std::tanh(0.4 * std::log(c.luminance_cd_m2 * c.field_x_deg * c.field_y_deg / (40.0 * 40.0)));
}

double RetinalIlluminanceTrolands(double luminance_cd_m2, double pupil_diameter_mm) {
  const double d = pupil_diameter_mm;
  return std::numbers::pi * d * d / 4 * luminance_cd_m2 * (1 - std::pow(d / 9.7, 2) + std::pow(d / 12.4, 4));
}

double BartenContrastSensitivity(double u, const BartenConditions& c) {
  CheckPositive(c.luminance_cd_m2, "luminance (cd/m2)");
  CheckPositive(c.field_x_deg, "field x (deg)");
  CheckPositive(c.field_y_deg, "field y (deg)");
  if (c.pupil_diameter_mm) CheckPositive(*c.pupil_diameter_mm, "pupil diameter (mm)");
  if (!(u >= 0) || !std::isfinite(u)) throw Error("Barten CSF: frequency " + std::to_string(u) + ": must be 0 or more");
  if (u == 0) return 0;
  const double d = c.pupil_diameter_mm.value_or(BartenPupilDiameterMm(c));
  const double sigma = std::hypot(kSigma0Deg, kCabDegPerMm * d);
  const double optics = std::exp(-2 * std::numbers::pi * std::numbers::pi * sigma * sigma * u * u);
  const double e = RetinalIlluminanceTrolands(c.luminance_cd_m2, d);
  const double area = AngularSize(u, c.field_x_deg) * AngularSize(u, c.field_y_deg);
  const double noise = 1 / (kEta * kP * e) + kPhi0 / (1 - std::exp(-(u / kU0) * (u / kU0)));
  return (optics / kK) / std::sqrt(2 / kT / area * noise);
}

}  // namespace layerlab
