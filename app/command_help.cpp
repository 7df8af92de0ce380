#include "layerlab/app/command_help.h"

#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "layerlab/framework/params.h"

namespace layerlab::app {
namespace {

// "layerlab: error: PREFIXunknown command "WORD"; did you mean "NEAR"? ..." on stderr; the usage exit code.
int UnknownCommand(const std::string& prefix, const std::string& word, const std::vector<std::string>& names) {
  std::string error = "layerlab: error: " + prefix + "unknown command \"" + word + "\"";
  if (std::optional<std::string> near = ClosestWord(word, names)) error += "; did you mean \"" + *near + "\"?";
  std::fprintf(stderr, "%s (layerlab help lists them)\n", error.c_str());
  return 2;
}

}  // namespace

std::optional<int> HelpOrUnknownCommand(CLI::App& app, int argc, char** argv) {
  if (argc < 2 || argv[1][0] == '-') return std::nullopt;  // options, or nothing: CLI11's own
  std::vector<std::string> names;
  for (const CLI::App* cmd : app.get_subcommands({})) names.push_back(cmd->get_name());
  const std::string word = argv[1];
  if (word == "help") {
    if (argc == 2) {
      std::cout << app.help();
      return 0;
    }
    for (CLI::App* cmd : app.get_subcommands({}))
      if (cmd->get_name() == argv[2]) {
        std::cout << cmd->help();
        return 0;
      }
    return UnknownCommand("help: ", argv[2], names);
  }
  for (const std::string& name : names)
    if (name == word) return std::nullopt;
  return UnknownCommand("", word, names);
}

}  // namespace layerlab::app
