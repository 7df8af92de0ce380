#include "layerlab/framework/warnings.h"

#include <cstdio>

namespace layerlab {

void SayWarnings(const std::vector<std::string>& texts, const std::string& prefix) {
  for (const std::string& t : texts) std::fprintf(stderr, "warning: %s%s\n", prefix.c_str(), t.c_str());
}

std::string WarningLines(const std::vector<std::string>& texts) {
  std::string out;
  for (const std::string& t : texts) out += "warning: " + t + "\n";
  return out;
}

}  // namespace layerlab
