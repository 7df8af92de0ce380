#include "layerlab/app/command_line.h"

namespace layerlab::app {
namespace {

std::string& Stored() {
  static std::string line = "layerlab";
  return line;
}

std::string Quoted(const std::string& arg) {
  if (!arg.empty() &&
      arg.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789-_./,=:+@") ==
          std::string::npos)
    return arg;
  std::string out = "'";
  for (char c : arg) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

}  // namespace

void SetCommandLine(int argc, const char* const* argv) {
  std::string line = "layerlab";  // the program's own path says nothing to a reader
  for (int k = 1; k < argc; ++k) line += " " + Quoted(argv[k]);
  Stored() = line;
}

const std::string& CommandLine() { return Stored(); }

}  // namespace layerlab::app
