#include "layerlab/framework/error.h"

namespace layerlab {

Location Location::child(const std::string& key) const { return {file, pointer + "/" + EscapePointerToken(key)}; }

Location Location::child(size_t index) const { return {file, pointer + "/" + std::to_string(index)}; }

std::string Location::str() const {
  std::string p = pointer.empty() ? "/" : pointer;
  return file.empty() ? p : file + ": " + p;
}

Error::Error(const std::string& message) : std::runtime_error(message), message_(message) {}

Error::Error(const Location& where, const std::string& message)
    : std::runtime_error(where.str() + ": " + message), where_(where), message_(message) {}

std::string EscapePointerToken(const std::string& token) {
  std::string out;
  for (char c : token) {
    if (c == '~')
      out += "~0";
    else if (c == '/')
      out += "~1";
    else
      out += c;
  }
  return out;
}

}  // namespace layerlab
