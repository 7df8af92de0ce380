#include "app/number_list.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "framework/error.h"

namespace layerlab::app {

std::vector<double> ParseNumberList(const std::string& text, const std::string& option) {
  std::vector<double> values;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    try {
      size_t used = 0;
      values.push_back(std::stod(item, &used));
      if (used != item.size()) throw std::invalid_argument(item);
    } catch (const std::exception&) {
      throw Error(option + ": \"" + item + "\" is not a number (give a comma-separated list such as 0.7,1.3,1.9)");
    }
    if (!std::isfinite(values.back()) || values.back() < 0) throw Error(option + ": values must be finite and >= 0");
  }
  if (values.empty()) throw Error(option + ": give at least one value");
  return values;
}

std::vector<double> ParseRange(const std::string& text, const std::string& option) {
  std::vector<double> r = ParseNumberList(text, option);
  if (r.size() != 3) throw Error(option + ": give first,last,step");
  if (!(r[1] > r[0]) || !(r[2] > 0)) throw Error(option + ": last must exceed first and step must be above 0");
  if ((r[1] - r[0]) / r[2] > 1e5) throw Error(option + ": more than 100000 steps");
  std::vector<double> values;
  for (int k = 0;; ++k) {
    double v = r[0] + k * r[2];
    if (v > r[1] + 1e-9 * r[2]) break;
    values.push_back(v);
  }
  return values;
}

}  // namespace layerlab::app
