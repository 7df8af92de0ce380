#include "layerlab/framework/units.h"

#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <optional>
#include <regex>

#include "layerlab/framework/error.h"

namespace layerlab {
namespace {

struct Unit {
  std::string_view symbol;
  Dimension dimension;
  double to_si;
};

constexpr std::array kUnits = {
    Unit{"m", Dimension::kLength, 1.0},
    Unit{"cm", Dimension::kLength, 1e-2},
    Unit{"mm", Dimension::kLength, 1e-3},
    Unit{"um", Dimension::kLength, 1e-6},
    Unit{"\xC2\xB5m", Dimension::kLength, 1e-6},  // U+00B5 micro sign
    Unit{"\xCE\xBCm", Dimension::kLength, 1e-6},  // U+03BC greek mu
    Unit{"nm", Dimension::kLength, 1e-9},
    Unit{"D", Dimension::kOpticalPower, 1.0},
    Unit{"dpt", Dimension::kOpticalPower, 1.0},
    Unit{"rad", Dimension::kAngle, 1.0},
    Unit{"mrad", Dimension::kAngle, 1e-3},
    Unit{"deg", Dimension::kAngle, kRadiansPerDegree},
    Unit{"\xC2\xB0", Dimension::kAngle, kRadiansPerDegree},  // degree sign
    Unit{"arcmin", Dimension::kAngle, kRadiansPerDegree / 60.0},
    Unit{"cd/m2", Dimension::kLuminance, 1.0},
    Unit{"cd/m^2", Dimension::kLuminance, 1.0},
    Unit{"nit", Dimension::kLuminance, 1.0},
    Unit{"nits", Dimension::kLuminance, 1.0},
    Unit{"cpd", Dimension::kAngularFrequency, 1.0},
    Unit{"%", Dimension::kFraction, 1e-2},
    Unit{"s", Dimension::kTime, 1.0},
    Unit{"ms", Dimension::kTime, 1e-3},
    Unit{"min", Dimension::kTime, 60.0},
    Unit{"Hz", Dimension::kFrequency, 1.0},
    Unit{"kHz", Dimension::kFrequency, 1e3},
};

std::optional<Unit> FindUnit(std::string_view symbol) {
  for (const Unit& u : kUnits)
    if (u.symbol == symbol) return u;
  return std::nullopt;
}

struct Split {
  double number;
  std::string_view unit;
};

Split SplitNumberAndUnit(std::string_view text) {
  while (!text.empty() && text.front() == ' ') text.remove_prefix(1);
  while (!text.empty() && text.back() == ' ') text.remove_suffix(1);
  double value = 0.0;
  auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec == std::errc::result_out_of_range) throw Error("the number in \"" + std::string(text) + "\" is out of range");
  if (ec != std::errc() || end == text.data())
    throw Error("\"" + std::string(text) + "\" does not start with a number");
  std::string_view unit(end, text.data() + text.size() - end);
  while (!unit.empty() && unit.front() == ' ') unit.remove_prefix(1);
  if (!std::isfinite(value)) throw Error("\"" + std::string(text) + "\" is not a finite number");
  return {value, unit};
}

}  // namespace

std::string DimensionName(Dimension d) {
  switch (d) {
    case Dimension::kLength:
      return "a length";
    case Dimension::kOpticalPower:
      return "an optical power";
    case Dimension::kAngle:
      return "an angle";
    case Dimension::kLuminance:
      return "a luminance";
    case Dimension::kAngularFrequency:
      return "an angular frequency";
    case Dimension::kFraction:
      return "a fraction";
    case Dimension::kTime:
      return "a duration";
    case Dimension::kFrequency:
      return "a frequency";
  }
  return "a quantity";
}

std::string AcceptedUnits(Dimension d) {
  std::string out;
  for (const Unit& u : kUnits) {
    if (u.dimension != d || u.symbol.front() & 0x80) continue;  // list ASCII spellings only
    if (!out.empty()) out += ", ";
    out += u.symbol;
  }
  return out;
}

std::string SIUnit(Dimension d) {
  for (const Unit& u : kUnits)
    if (u.dimension == d && u.to_si == 1.0) return std::string(u.symbol);
  return "";
}

double ParseQuantity(std::string_view text, Dimension d) {
  Split s = SplitNumberAndUnit(text);
  if (s.unit.empty()) {
    if (d == Dimension::kFraction) return s.number;
    throw Error("\"" + std::string(text) + "\" has no unit; expected " + DimensionName(d) + " in " + AcceptedUnits(d));
  }
  std::optional<Unit> unit = FindUnit(s.unit);
  if (!unit)
    throw Error("unknown unit '" + std::string(s.unit) + "' in \"" + std::string(text) + "\"; expected " +
                DimensionName(d) + " in " + AcceptedUnits(d));
  if (unit->dimension != d)
    throw Error("'" + std::string(s.unit) + "' is " + DimensionName(unit->dimension) + " unit; expected " +
                DimensionName(d) + " in " + AcceptedUnits(d));
  double value = s.number * unit->to_si;
  if (!std::isfinite(value)) throw Error("\"" + std::string(text) + "\" is out of range");
  return value;
}

Depth ParseDepth(std::string_view text) {
  Split s = SplitNumberAndUnit(text);
  std::optional<Unit> unit = s.unit.empty() ? std::nullopt : FindUnit(s.unit);
  if (unit && unit->dimension == Dimension::kOpticalPower) {
    if (s.number < 0) throw Error("a depth of " + std::string(text) + " is behind the eye");
    return {s.number};
  }
  if (unit && unit->dimension == Dimension::kLength) {
    double meters = s.number * unit->to_si;
    if (!(meters > 0)) throw Error("a depth of " + std::string(text) + " is not in front of the eye");
    // Below about 1e-308 m (subnormal) the power 1 / meters overflows to inf.
    if (!std::isfinite(1.0 / meters))
      throw Error("a depth of " + std::string(text) + " is too close to the eye (its optical power is not finite)");
    return {1.0 / meters};
  }
  throw Error("\"" + std::string(text) + "\" is not a depth; expected diopters (D) or a distance in " +
              AcceptedUnits(Dimension::kLength));
}

std::optional<std::pair<double, std::string>> NumberWithUnit(const std::string& text) {
  // std::regex recurses per character: a label of 200000 digits overflowed the stack. No number
  // with a unit is this long.
  if (text.size() > 64) return std::nullopt;
  static const std::regex form(R"(\s*([-+]?[0-9]*\.?[0-9]+(?:[eE][-+]?[0-9]+)?)\s*([^\s0-9][^\s]*)?\s*)");
  std::smatch m;
  if (!std::regex_match(text, m, form)) return std::nullopt;
  return std::make_pair(std::strtod(m[1].str().c_str(), nullptr), m[2].str());
}

std::string FormatGeneral(double value) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", value);
  return buf;
}

std::string FormatFixed(double value, int decimals) {
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, value);
  return buf;
}

}  // namespace layerlab
