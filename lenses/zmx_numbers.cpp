#include "layerlab/lenses/zmx_numbers.h"

#include <charconv>
#include <cmath>
#include <system_error>

namespace layerlab::lenses::zmx {
namespace {

double UnitPower(int power, double meters_per_unit) {
  double scale = 1.0;
  for (int i = 0; i < (power < 0 ? -power : power); ++i) scale *= meters_per_unit;
  return scale;
}

std::string Format(double value, int digits) {
  char text[64];
  const std::to_chars_result r = std::to_chars(text, text + sizeof text, value, std::chars_format::general, digits);
  std::string s(text, r.ptr);
  for (char& c : s) {
    if (c == 'e') c = 'E';
  }
  return s;
}

bool ReadsBackAs(const std::string& text, int power, double meters_per_unit, double value_si) {
  const std::optional<double> v = ParseNumber(text);
  return v && ToMeters(*v, power, meters_per_unit) == value_si;
}

}  // namespace

std::optional<double> ParseNumber(std::string_view token) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  if (token.empty()) return std::nullopt;
  const char first = token.front() == '-' && token.size() > 1 ? token[1] : token.front();
  if (!(first == '.' || (first >= '0' && first <= '9'))) return std::nullopt;  // no "inf", "nan"
  double value = 0.0;
  const std::from_chars_result r =
      std::from_chars(token.data(), token.data() + token.size(), value, std::chars_format::general);
  if (r.ec != std::errc() || r.ptr != token.data() + token.size() || !std::isfinite(value)) return std::nullopt;
  return value;
}

std::optional<double> MetersPerUnit(std::string_view unit) {
  if (unit == "MM") return 1e-3;
  if (unit == "CM") return 1e-2;
  if (unit == "IN") return 0.0254;
  if (unit == "METER") return 1.0;
  return std::nullopt;
}

double ToMeters(double value, int power, double meters_per_unit) {
  const double scale = UnitPower(power, meters_per_unit);
  return power >= 0 ? value * scale : value / scale;
}

double FromMeters(double value_si, int power, double meters_per_unit) {
  const double scale = UnitPower(power, meters_per_unit);
  return power >= 0 ? value_si / scale : value_si * scale;
}

std::string FormatExact(double value_si, int power, double meters_per_unit) {
  const double nearest = FromMeters(value_si, power, meters_per_unit);
  for (int digits = 1; digits <= 17; ++digits) {
    const std::string text = Format(nearest, digits);
    if (ReadsBackAs(text, power, meters_per_unit, value_si)) return text;
  }
  // The conversion rounds twice: the lens-unit number that maps back may lie an ulp or two away.
  double below = nearest, above = nearest;
  for (int step = 0; step < 4; ++step) {
    below = std::nextafter(below, -HUGE_VAL);
    above = std::nextafter(above, HUGE_VAL);
    for (double candidate : {below, above}) {
      const std::string text = Format(candidate, 17);
      if (ReadsBackAs(text, power, meters_per_unit, value_si)) return text;
    }
  }
  return Format(nearest, 17);
}

}  // namespace layerlab::lenses::zmx
