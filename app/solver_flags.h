// The solve command's flags for the solver options, one per entry of the
// option table (solvers/solver_option_table.h) that names a flag; --target
// and --target-scene are app/target_option.h's, shared with other commands.
#pragma once

#include <map>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "layerlab/solvers/solve_config.h"

namespace layerlab::app {

// What was given, by option key. Registered in place: keep it where AddSolverFlags saw it.
struct SolverFlags {
  std::string solver, sampling;
  std::map<std::string, std::optional<int>> integers;
  std::map<std::string, std::optional<double>> reals;
  std::map<std::string, std::string> texts;  // choices, and quantities with a unit ("2 min")
  std::map<std::string, bool> switches;
};

void AddSolverFlags(CLI::App* cmd, SolverFlags& flags);

// Sets what was given over config (the scene's values); a choice not among
// the table's is refused here, a value out of range by SolverOptions::IsValid.
void ApplySolverFlags(const SolverFlags& flags, SolveConfig& config);

}  // namespace layerlab::app
