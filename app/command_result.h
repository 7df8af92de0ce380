// A command's result on stdout (docs/cli.md, "Results"): lines for a reader
// as the command goes, or with --json one JSON object when it is done:
//   {"command": "solve", "layerlab_version": "0.9.0", "git_commit": "441ea22", ...the command's fields}
// Progress, notes and warnings stay on stderr either way. A failed command
// prints the same head with "error" and "exit_status" instead (PrintFailure).
#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace layerlab::app {

class CommandResult {
 public:
  explicit CommandResult(std::string command);
  CommandResult(const CommandResult&) = delete;
  CommandResult& operator=(const CommandResult&) = delete;

  // Printed on stdout now, unless --json.
  void Text(const std::string& text) const;
  // The JSON object's field `key` (set what the command measured, in the units its name says).
  nlohmann::ordered_json& operator[](const std::string& key) { return fields_[key]; }
  // With --json: the object on stdout. Call once, when the command is done.
  void Print() const;

 private:
  std::string command_;
  nlohmann::ordered_json fields_ = nlohmann::ordered_json::object();
};

// When `json` (--json was given), the failure of `command` (the subcommand's name, "" before one was
// named) as one JSON object.
void PrintFailure(const std::string& command, const std::string& error, int exit_status, bool json);

}  // namespace layerlab::app
