// The solve command's flags for the solver options, one per entry of the
// option table (solvers/solver_option_table.h) that names a flag (made by
// app/option_flags.h); --target and --target-scene are app/target_option.h's,
// shared with other commands.
#pragma once

#include <string>

#include <CLI/CLI.hpp>

#include "layerlab/app/option_flags.h"
#include "layerlab/solvers/solve_config.h"

namespace layerlab::app {

// What was given, by option key, and the solve's own --solver and --sampling.
struct SolverFlags : OptionFlags {
  std::string solver, sampling;
};

void AddSolverFlags(CLI::App* cmd, SolverFlags& flags);

// Sets what was given over config (the scene's values); a choice not among
// the table's is refused here, a value out of range by SolverOptions::IsValid.
void ApplySolverFlags(const SolverFlags& flags, SolveConfig& config);

}  // namespace layerlab::app
