// Every option of a solve, described once: its scene key, type, range,
// default, meaning, command-line flag and Python keyword. The scene reader
// (solve_config.cpp), SolverOptions::IsValid, the solve command's flags
// (app/solver_flags.cpp), Python's solve() keywords (python/src/solve.cpp)
// and docs/scene-reference.md are all made from this table;
// tests/solver_option_table_test.cpp, tests/cli/solver_option_flags.py and
// python/tests/test_solver_option_table.py fail when one of them disagrees
// with it. The entries' shape is every option table's (framework/option_table.h).
#pragma once

#include <string>
#include <vector>

#include "layerlab/framework/option_table.h"
#include "layerlab/solvers/types.h"

namespace layerlab {

using SolverOptionKind = OptionKind;
using SolverOptionEntry = OptionEntry<SolverOptions>;

// In the reference's order.
const std::vector<SolverOptionEntry>& SolverOptionTable();
// The entry of `key`, or nullptr.
const SolverOptionEntry* FindSolverOption(const std::string& key);
// "" when `value` lies in the range of option `key`, else IsValid's message for it under the name `name`
// ("--iterations: 0: must be in [1, 1000000]"): one wording for every command that takes the option.
std::string SolverOptionProblem(const std::string& key, double value, const std::string& name);

}  // namespace layerlab
