#include "layerlab/framework/option_table.h"

#include <cmath>
#include <sstream>

#include "layerlab/framework/params.h"

namespace layerlab {

bool OptionRange::Contains(double v) const {
  if (std::isnan(v)) return false;
  return (min_open ? v > min : v >= min) && (max_open ? v < max : v <= max);
}

std::string OptionRange::Text(bool integer) const {
  auto number = [&](double v) {
    if (integer) return std::to_string(static_cast<long long>(v));
    std::ostringstream s;
    s << v;
    return s.str();
  };
  return (min_open ? "(" : "[") + number(min) + ", " + number(max) + (max_open ? ")" : "]");
}

std::string OptionSpec::Constraint() const {
  return "must be in " + range.Text(kind == OptionKind::kInteger) + constraint_note;
}

std::string OptionSpec::ChoiceList() const { return JoinWords(choices); }

int OptionSpec::ChoiceIndex(const std::string& name) const {
  for (size_t i = 0; i < choices.size(); ++i)
    if (choices[i] == name) return static_cast<int>(i);
  return -1;
}

std::string OptionSpec::FieldUnit() const { return unit.empty() ? SIUnit(dimension) : unit; }

double OptionSpec::FieldUnitInSI() const { return unit.empty() ? 1 : ParseQuantity("1 " + unit, dimension); }

std::string OptionViolation(const std::string& field, double value, const std::string& constraint) {
  std::ostringstream s;
  s << field << ": " << value << ": " << constraint;
  return s.str();
}

}  // namespace layerlab
