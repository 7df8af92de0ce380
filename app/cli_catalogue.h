// Every command and option of the command line, read from the CLI11 tree that
// parses it, so that what documents the command line cannot drift from it:
// `layerlab help --json`, the bash and zsh completions and the man page
// (`layerlab help --completion bash|zsh`, `layerlab help --man`; the build
// writes them and installs them beside the program), and the vocabulary test
// against docs/cli.md.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace CLI {
class App;
}

namespace layerlab::app {

struct CliOption {
  std::vector<std::string> names;  // "--out", or "-q", "--quiet"; a positional's name ("scene")
  bool positional = false;
  bool takes_value = false;  // a flag takes none
  bool required = false;
  bool repeatable = false;           // a positional that takes several ("scenes...")
  std::vector<std::string> choices;  // when the value is one of these
  std::string help;
};

struct CliCommand {
  std::string name, description;
  std::vector<CliOption> options;  // --help first, then as registered
};

// The top-level command (name "layerlab": its own options) and then each subcommand, in registration order.
std::vector<CliCommand> Catalogue(const CLI::App& app);

nlohmann::json CatalogueJson(const std::vector<CliCommand>& catalogue);
std::string BashCompletion(const std::vector<CliCommand>& catalogue);
std::string ZshCompletion(const std::vector<CliCommand>& catalogue);
// layerlab(1) in roff (man -l layerlab.1).
std::string ManPage(const std::vector<CliCommand>& catalogue, const std::string& version);

}  // namespace layerlab::app
