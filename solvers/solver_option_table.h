// Every option of a solve, described once: its scene key, type, range,
// default, meaning, command-line flag and Python keyword. The scene reader
// (solve_config.cpp), SolverOptions::IsValid, the solve command's flags
// (app/solver_flags.cpp), Python's solve() keywords (python/src/solve.cpp)
// and docs/scene-reference.md are all made from this table;
// tests/solver_option_table_test.cpp and tests/cli/solver_option_consumers.py
// fail when one of them disagrees with it.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "layerlab/framework/units.h"
#include "layerlab/solvers/types.h"

namespace layerlab {

enum class SolverOptionKind {
  kInteger,  // an int field, range checked
  kSeed,     // the uint64 seed
  kReal,     // a double field, range checked; a quantity of `dimension` in the scene
  kChoice,   // one of `choices`, stored as an enum
  kBoolean,  // on the command line a flag that sets it
  kConfig,   // a SolveConfig field (solver, target, sampling): read by its consumers by hand
};

// [min, max], either end open; `integer`: printed without an exponent.
struct OptionRange {
  double min = 0, max = 0;
  bool min_open = false, max_open = false;
  bool Contains(double v) const;
  std::string Text(bool integer) const;  // "[1, 1000000]", "(0, 0.1)"
};

struct SolverOptionEntry {
  std::string key;  // the scene's "solve" key, IsValid's field name and (unless `python` says otherwise) Python's
  SolverOptionKind kind = SolverOptionKind::kConfig;
  std::string type;  // the reference's type cell: "integer", "time", "fraction", "clip, scale", ...
  bool in_scene = true;
  Dimension dimension = Dimension::kFraction;  // kReal in the scene: kTime or kFraction (a bare number or %)
  bool has_range = false;
  OptionRange range;
  std::string constraint_note;  // after IsValid's "must be in [a, b]": " (0 = all cores)"
  std::string default_text;
  std::string meaning;
  std::string cli_flag;  // "" when the solve command has none
  std::string cli_help;
  std::string python;  // the keyword of layerlab.solve(), "" when none
  std::vector<std::string> choices;
  // Field access (kInteger, kReal, kSeed: the member; kChoice: the index in `choices`; kBoolean: 0 or 1).
  int SolverOptions::*integer = nullptr;
  double SolverOptions::*real = nullptr;
  uint64_t SolverOptions::*seed = nullptr;
  int (*get)(const SolverOptions&) = nullptr;
  void (*set)(SolverOptions&, int) = nullptr;

  // The value as IsValid compares it with the range (kInteger, kReal).
  double Number(const SolverOptions& o) const;
  // "must be in [1, 1000000]" and the note: the constraint of IsValid's "field: value: constraint".
  std::string Constraint() const;
  // "clip or scale".
  std::string ChoiceList() const;
  // The index of `name` in `choices`, or -1.
  int ChoiceIndex(const std::string& name) const;
};

// In the reference's order.
const std::vector<SolverOptionEntry>& SolverOptionTable();
// The entry of `key`, or nullptr.
const SolverOptionEntry* FindSolverOption(const std::string& key);

}  // namespace layerlab
