// Numbers on the command line, read as the scene files read them: each value
// is a quantity with a unit ("1.0 D", "5 s", "0.05 deg", "2 cpd"; see
// framework/units.h) or a bare number in the option's own unit, as before
// ("1.0" for --accommodation is 1.0 D). Lists are comma-separated
// ("0.7 D,1.3 D"); a range is FROM:TO:STEP ("0:2.6:0.05"). A bad value is refused with the option's name and the value.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "layerlab/framework/units.h"

namespace layerlab::app {

// What a bare number means for an option: its dimension and unit ("D", "s", "deg", "cpd").
struct OptionUnit {
  Dimension dimension;
  std::string unit;
};
inline const OptionUnit kDiopters{Dimension::kOpticalPower, "D"};
inline const OptionUnit kSeconds{Dimension::kTime, "s"};
inline const OptionUnit kDegrees{Dimension::kAngle, "deg"};
inline const OptionUnit kCyclesPerDegree{Dimension::kAngularFrequency, "cpd"};
inline const OptionUnit kMillimeters{Dimension::kLength, "mm"};
inline const OptionUnit kArcminutes{Dimension::kAngle, "arcmin"};

// One finite value >= 0, in the option's unit. A depth in diopters also
// accepts a distance ("0.5 m" is 2 D) when `depth` is set.
double ParseOptionValue(const std::string& text, const std::string& option, const OptionUnit& unit, bool depth = false);

// "X,Y": two finite values of either sign ("1 mm,-0.5 mm"), as ParseOptionValue reads each.
std::array<double, 2> ParseSignedPair(const std::string& text, const std::string& option, const OptionUnit& unit);

// Comma-separated values, each as ParseOptionValue reads it.
std::vector<double> ParseNumberList(const std::string& text, const std::string& option, const OptionUnit& unit,
                                    bool depth = false);

// "FROM:TO:STEP" (all >= 0, TO > FROM, STEP > 0; each a quantity as
// ParseOptionValue reads it) as the values FROM, FROM + STEP, ... up to TO
// (inclusive within rounding).
std::vector<double> ParseRange(const std::string& text, const std::string& option, const OptionUnit& unit);
// The three numbers of a range, checked as ParseRange checks them.
std::vector<double> ParseRangeBounds(const std::string& text, const std::string& option, const OptionUnit& unit);

// Comma-separated items, each a value or a range FROM:TO:STEP, in order: "0.4,1:2:0.5" is 0.4, 1, 1.5, 2.
std::vector<double> ParseStates(const std::string& text, const std::string& option, const OptionUnit& unit,
                                bool depth = false);

}  // namespace layerlab::app
