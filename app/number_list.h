// Comma-separated numbers on the command line ("0.4,1.0,1.6,2.2"), refused
// with the option's name when an item is not a finite number >= 0.
#pragma once

#include <string>
#include <vector>

namespace layerlab::app {

std::vector<double> ParseNumberList(const std::string& text, const std::string& option);

// "first,last,step" (all >= 0, last > first, step > 0) as the values
// first, first + step, ... up to last (inclusive within rounding).
std::vector<double> ParseRange(const std::string& text, const std::string& option);

}  // namespace layerlab::app
