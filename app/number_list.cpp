#include "layerlab/app/number_list.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "layerlab/framework/error.h"

namespace layerlab::app {
namespace {

std::string Trimmed(const std::string& text) {
  const size_t first = text.find_first_not_of(" \t");
  if (first == std::string::npos) return "";
  return text.substr(first, text.find_last_not_of(" \t") - first + 1);
}

// A bare number or a quantity, of either sign; finite.
double ParseSignedValue(const std::string& text, const std::string& option, const OptionUnit& unit, bool depth) {
  const std::string item = Trimmed(text);
  double value = 0;
  size_t used = 0;
  try {
    value = std::stod(item, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != item.size()) {
    // Not a bare number: a quantity with its unit, in SI, then in the option's unit.
    try {
      value = depth && unit.dimension == Dimension::kOpticalPower
                  ? ParseDepth(item).diopters
                  : ParseQuantity(item, unit.dimension) / ParseQuantity("1 " + unit.unit, unit.dimension);
    } catch (const Error& e) {
      throw Error(option + ": \"" + item + "\" is not a number or " + DimensionName(unit.dimension) + " (" +
                  e.message() + "; give e.g. 1.5 or \"1.5 " + unit.unit + "\")");
    }
  }
  if (!std::isfinite(value)) throw Error(option + ": \"" + item + "\": values must be finite");
  return value;
}

}  // namespace

double ParseOptionValue(const std::string& text, const std::string& option, const OptionUnit& unit, bool depth) {
  const double value = ParseSignedValue(text, option, unit, depth);
  if (value < 0) throw Error(option + ": \"" + Trimmed(text) + "\": values must be finite and >= 0");
  return value;
}

std::array<double, 2> ParseSignedPair(const std::string& text, const std::string& option, const OptionUnit& unit) {
  std::vector<std::string> items;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');) items.push_back(item);
  if (items.size() != 2)
    throw Error(option + ": give X,Y (\"" + text + "\" has " + std::to_string(items.size()) + " value" +
                (items.size() == 1 ? "" : "s") + ")");
  return {ParseSignedValue(items[0], option, unit, false), ParseSignedValue(items[1], option, unit, false)};
}

std::vector<double> ParseNumberList(const std::string& text, const std::string& option, const OptionUnit& unit,
                                    bool depth) {
  std::vector<double> values;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) values.push_back(ParseOptionValue(item, option, unit, depth));
  if (values.empty()) throw Error(option + ": give at least one value");
  return values;
}

std::vector<double> ParseRangeBounds(const std::string& text, const std::string& option, const OptionUnit& unit) {
  std::vector<std::string> items;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ':');) items.push_back(item);
  if (items.size() != 3 || text.find(',') != std::string::npos)
    throw Error(option + ": \"" + text + "\": give a range FROM:TO:STEP, e.g. 0:2.6:0.05 (a comma-separated list " +
                "is a list of values)");
  const std::vector<double> r = {ParseOptionValue(items[0], option, unit), ParseOptionValue(items[1], option, unit),
                                 ParseOptionValue(items[2], option, unit)};
  if (!(r[1] > r[0]) || !(r[2] > 0))
    throw Error(option + ": \"" + text + "\": TO must exceed FROM and STEP must be above 0");
  if ((r[1] - r[0]) / r[2] > 1e5) throw Error(option + ": \"" + text + "\": more than 100000 steps");
  return r;
}

std::vector<double> ParseRange(const std::string& text, const std::string& option, const OptionUnit& unit) {
  const std::vector<double> r = ParseRangeBounds(text, option, unit);
  std::vector<double> values;
  for (int k = 0;; ++k) {
    double v = r[0] + k * r[2];
    if (v > r[1] + 1e-9 * r[2]) break;
    values.push_back(v);
  }
  return values;
}

std::vector<double> ParseStates(const std::string& text, const std::string& option, const OptionUnit& unit,
                                bool depth) {
  std::vector<double> values;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');) {
    if (item.find(':') == std::string::npos) {
      values.push_back(ParseOptionValue(item, option, unit, depth));
    } else {
      const std::vector<double> range = ParseRange(item, option, unit);
      values.insert(values.end(), range.begin(), range.end());
    }
  }
  if (values.empty()) throw Error(option + ": give at least one value");
  return values;
}

}  // namespace layerlab::app
