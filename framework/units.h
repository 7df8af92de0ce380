// Quantities with units on the way in: "75 mm", "117 um", "0.4 D", "36 deg".
// Inside layerlab everything is SI: meters, diopters (1/m), radians, cd/m^2.
#pragma once

#include <numbers>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

namespace layerlab {

// The one home of the angle conversions: radians = degrees * kRadiansPerDegree,
// degrees = radians * kDegreesPerRadian.
inline constexpr double kRadiansPerDegree = std::numbers::pi / 180;
inline constexpr double kDegreesPerRadian = 180 / std::numbers::pi;

enum class Dimension {
  kLength,            // m, cm, mm, um, nm
  kOpticalPower,      // D (diopters, 1/m)
  kAngle,             // rad, mrad, deg, arcmin
  kLuminance,         // cd/m2, nit
  kAngularFrequency,  // cpd (cycles per degree)
  kFraction,          // bare number or %
  kTime,              // s, ms, min
  kFrequency,         // Hz, kHz
};

// "a length", "an angle", ... for messages.
std::string DimensionName(Dimension d);
// The units a dimension accepts, for messages: "m, cm, mm, um, nm".
std::string AcceptedUnits(Dimension d);
// The dimension's SI unit, the first it accepts at a factor of 1 ("m", "D",
// "rad", "cpd", "s"); "" for a fraction.
std::string SIUnit(Dimension d);

// Parses "75 mm" into SI (0.075). A bare number (JSON number) is taken as
// SI by the caller; this parses strings only. Throws layerlab::Error with
// a location-free message on a bad unit, wrong dimension or non-finite value.
double ParseQuantity(std::string_view text, Dimension d);

// A depth in eye space, given as a distance ("2.5 m") or an optical
// power ("0.4 D"). Stored as diopters so that infinity (0 D) stays finite.
struct Depth {
  double diopters = 0.0;
};
Depth ParseDepth(std::string_view text);

// A label as a number and the unit written after it, without converting:
// "1.2 D" -> (1.2, "D"), "0.5" -> (0.5, ""); anything else (or more than 64
// characters) -> nothing.
std::optional<std::pair<double, std::string>> NumberWithUnit(const std::string& text);

// Formats a value in a chosen unit with fixed decimals: "72.81 mm".
std::string FormatFixed(double value, int decimals);
// A value in six significant digits, for messages: "1e-09", "170", "0.05" (printf's %g).
std::string FormatGeneral(double value);

}  // namespace layerlab
