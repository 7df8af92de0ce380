#include "layerlab/app/command_result.h"

#include <cstdio>
#include <iostream>
#include <utility>

#include "layerlab/app/global_flags.h"
#include "layerlab/framework/version.h"

namespace layerlab::app {
namespace {

bool& Printed() {
  static bool printed = false;  // a command prints one object: its result, or its failure
  return printed;
}

nlohmann::ordered_json Head(const std::string& command) {
  nlohmann::ordered_json j = nlohmann::ordered_json::object();
  j["command"] = command;
  j["layerlab_version"] = Version();
  j["git_commit"] = GitCommit();
  return j;
}

}  // namespace

CommandResult::CommandResult(std::string command) : command_(std::move(command)) {}

void CommandResult::Text(const std::string& text) const {
  if (JsonRequested()) return;
  std::fputs(text.c_str(), stdout);
  std::fflush(stdout);
}

void CommandResult::Print() const {
  if (!JsonRequested()) return;
  nlohmann::ordered_json j = Head(command_);
  j.update(fields_);
  std::cout << j.dump(2) << std::endl;
  Printed() = true;
}

void PrintFailure(const std::string& command, const std::string& error, int exit_status, bool json) {
  if (!json || Printed()) return;  // an interrupted solve has printed what it kept
  nlohmann::ordered_json j = Head(command);
  j["error"] = error;
  j["exit_status"] = exit_status;
  std::cout << j.dump(2) << std::endl;
}

}  // namespace layerlab::app
