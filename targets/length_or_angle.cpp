#include "layerlab/targets/length_or_angle.h"

#include <numbers>

#include "layerlab/framework/json_file.h"

namespace layerlab {

double LengthOrAngle(Params& p, const std::string& key, double depth) {
  const nlohmann::json& v = p.raw(key);
  const char* expected = "expected a length such as \"12 mm\" or an angle such as \"1 deg\"";
  if (v.is_number()) p.fail(key, std::string("a bare number is ambiguous here; ") + expected);
  if (!v.is_string()) p.fail(key, std::string(expected) + ", got " + JsonKindName(v));
  std::string text = v.get<std::string>();
  double value = 0;
  try {
    value = ParseQuantity(text, Dimension::kLength);
  } catch (const Error&) {
    try {
      value = ParseQuantity(text, Dimension::kAngle) * depth;
    } catch (const Error&) {
      p.fail(key, std::string(expected) + ", got \"" + text + "\"");
    }
  }
  if (!(value > 0)) p.fail(key, "must be positive, got \"" + text + "\"");
  return value;
}

std::array<double, 2> LengthOrAnglePair(Params& p, const std::string& key, double depth) {
  const nlohmann::json& v = p.raw(key);
  if (!v.is_array()) {
    double both = LengthOrAngle(p, key, depth);
    return {both, both};
  }
  if (v.size() != 2) p.fail(key, "expected two values [width, height], got " + std::to_string(v.size()));
  Params pair(nlohmann::json{{"0", v[0]}, {"1", v[1]}}, p.where(key));
  return {LengthOrAngle(pair, "0", depth), LengthOrAngle(pair, "1", depth)};
}

double CyclesPerMeter(double cpd, double depth) { return cpd / (depth * std::numbers::pi / 180.0); }

}  // namespace layerlab
