#include "layerlab/app/command_help.h"

#include <cstdio>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "layerlab/app/cli_catalogue.h"
#include "layerlab/app/command_result.h"
#include "layerlab/app/exit_status.h"
#include "layerlab/app/global_flags.h"
#include "layerlab/framework/params.h"
#include "layerlab/framework/version.h"

namespace layerlab::app {
namespace {

std::vector<std::string> CommandNames(const CLI::App& app) {
  std::vector<std::string> names;
  for (const CLI::App* cmd : app.get_subcommands({})) names.push_back(cmd->get_name());
  return names;
}

// "unknown command "WORD"; did you mean "NEAR"? (layerlab help lists them)".
std::string UnknownCommandMessage(const std::string& word, const std::vector<std::string>& names) {
  std::string error = "unknown command \"" + word + "\"";
  if (std::optional<std::string> near = ClosestWord(word, names)) error += "; did you mean \"" + *near + "\"?";
  return error + " (layerlab help lists them)";
}

struct HelpRequest {
  std::string command, completion;
  bool man = false;
};

void PrintHelp(const CLI::App& app, const HelpRequest& r) {
  const std::vector<CliCommand> catalogue = Catalogue(app);
  if (!r.completion.empty()) {
    std::cout << (r.completion == "bash" ? BashCompletion(catalogue) : ZshCompletion(catalogue));
  } else if (r.man) {
    std::cout << ManPage(catalogue, Version());
  } else if (JsonRequested()) {
    CommandResult result("help");
    result["commands"] = CatalogueJson(catalogue)["commands"];
    result.Print();
  } else if (r.command.empty()) {  // app.help() would explain `help` itself, the command being run
    std::cout << app.get_formatter()->make_help(&app, app.get_name(), CLI::AppFormatMode::Normal);
  } else {
    for (const CLI::App* cmd : app.get_subcommands({}))
      if (cmd->get_name() == r.command) std::cout << cmd->help(app.get_name());
  }
}

}  // namespace

void AddHelpCommand(CLI::App& app) {
  auto r = std::make_shared<HelpRequest>();
  CLI::App* cmd = app.add_subcommand("help",
                                     "Help on every command or on one; with --json, every command and "
                                     "option for machines; a man page; shell completion");
  cmd->add_option("command", r->command, "The command to explain (default: all of them)");
  cmd->add_flag("--man", r->man, "Print the man page layerlab(1) in roff (man -l FILE)");
  cmd->add_option("--completion", r->completion, "Print the completion script for this shell")
      ->check(CLI::IsMember({"bash", "zsh"}));
  CLI::App* top = &app;
  cmd->callback([top, r] {
    if (!r->command.empty()) {
      const std::vector<std::string> names = CommandNames(*top);
      bool known = false;
      for (const std::string& n : names) known = known || n == r->command;
      if (!known) throw UsageError("help: " + UnknownCommandMessage(r->command, names));
    }
    PrintHelp(*top, *r);
  });
}

std::optional<int> RefuseUnknownCommand(const CLI::App& app, int argc, char** argv) {
  int k = 1;
  while (k < argc && IsGlobalFlag(argv[k])) ++k;
  if (k >= argc || argv[k][0] == '-') return std::nullopt;  // other options, or nothing: CLI11's own
  const std::vector<std::string> names = CommandNames(app);
  for (const std::string& name : names)
    if (name == argv[k]) return std::nullopt;
  const std::string error = UnknownCommandMessage(argv[k], names);
  std::fprintf(stderr, "layerlab: error: %s\n", error.c_str());
  bool json = false;  // not parsed yet
  for (int j = 1; j < argc; ++j) json = json || std::string(argv[j]) == "--json";
  PrintFailure("", error, kExitUsage, json);
  return kExitUsage;
}

}  // namespace layerlab::app
