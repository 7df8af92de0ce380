#include "layerlab/app/global_flags.h"

#include <cstdint>

#include <CLI/CLI.hpp>

#include "layerlab/app/exit_status.h"
#include "layerlab/framework/progress.h"

namespace layerlab::app {
namespace {

struct Given {
  bool quiet = false, verbose = false, json = false;
};

Given& Flags() {
  static Given given;
  return given;
}

void Add(CLI::App* cmd) {
  cmd->add_flag_function(
      "--quiet,-q",
      [](std::int64_t) {
        if (Flags().verbose) throw UsageError("--quiet and --verbose exclude each other");
        Flags().quiet = true;
        SetVerbosity(Verbosity::kQuiet);
      },
      "No progress or notes on stderr (errors and warnings remain)");
  cmd->add_flag_function(
      "--verbose,-v",
      [](std::int64_t) {
        if (Flags().quiet) throw UsageError("--quiet and --verbose exclude each other");
        Flags().verbose = true;
        SetVerbosity(Verbosity::kVerbose);
      },
      "Every step on stderr: each iteration of each run, one line each");
  cmd->add_flag_function(
      "--json", [](std::int64_t) { Flags().json = true; },
      "The result on stdout as one JSON object for machines (docs/cli.md); progress and notes stay on stderr");
}

}  // namespace

void AddGlobalFlags(CLI::App& app) {
  Add(&app);
  for (CLI::App* cmd : app.get_subcommands({})) Add(cmd);
}

bool IsGlobalFlag(const std::string& arg) {
  return arg == "-q" || arg == "--quiet" || arg == "-v" || arg == "--verbose" || arg == "--json";
}

bool JsonRequested() { return Flags().json; }

}  // namespace layerlab::app
