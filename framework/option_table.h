// An option described once, in a table of entries (key, type, unit, range,
// default, meaning, command-line flag, Python name) from which its consumers
// are made: the scene reader (framework/option_reader.h), the options'
// IsValid (RangesHold), the command's flags (app/option_flags.h), the Python
// keywords and docs/scene-reference.md (tools/scene_reference.cpp). The
// tables: solvers/solver_option_table.h, analysis/contrast_option_table.h,
// analysis/run_option_table.h.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "layerlab/framework/units.h"

namespace layerlab {

enum class OptionKind {
  kInteger,  // an int field, range checked
  kSeed,     // a uint64 field (the seed)
  kReal,     // a double field (or, with `list`, a std::vector<double> field, each item range checked; in the
             // scene a non-empty array), a quantity of `dimension` in the scene and of `unit` in the field
  kChoice,   // one of `choices`, stored as an enum
  kBoolean,  // on the command line a flag that sets it (or, set by default, clears it)
  kConfig,   // not a field of the options: read by its consumers by hand
};

// [min, max], either end open; `integer`: printed without an exponent.
struct OptionRange {
  double min = 0, max = 0;
  bool min_open = false, max_open = false;
  bool Contains(double v) const;
  std::string Text(bool integer) const;  // "[1, 1000000]", "(0, 0.1)"
};

// What a table says of one option, whatever struct holds it.
struct OptionSpec {
  std::string key;  // the scene's key, IsValid's field name and (unless `python` says otherwise) Python's
  OptionKind kind = OptionKind::kConfig;
  std::string type;  // the reference's type cell: "integer", "time", "fraction", "clip, scale", ...
  bool in_scene = true;
  Dimension dimension = Dimension::kFraction;  // kReal: the quantity's in the scene
  std::string unit;  // the field's unit when not SI ("deg"): what a bare number means on the command line
  bool has_range = false;
  OptionRange range;
  std::string constraint_note;  // after IsValid's "must be in [a, b]": " (0 = all cores)"
  std::string default_text;
  std::string meaning;
  std::string cli_flag;  // "" when the command has none
  std::string cli_help;
  std::string python;  // the Python keyword, "" when none
  std::vector<std::string> choices;

  // "must be in [1, 1000000]" and the note: the constraint of IsValid's "field: value: constraint".
  std::string Constraint() const;
  // "clip or scale".
  std::string ChoiceList() const;
  // The index of `name` in `choices`, or -1.
  int ChoiceIndex(const std::string& name) const;
  // The field's unit: `unit`, or the dimension's SI unit (SIUnit: "s", "rad", "D", "cpd", "m").
  std::string FieldUnit() const;
  // One `FieldUnit()` in SI (kRadiansPerDegree for "deg").
  double FieldUnitInSI() const;
};

template <class Options>
struct OptionEntry : OptionSpec {
  // Field access (kInteger, kReal, kSeed: the member; kChoice: the index in `choices`; kBoolean: 0 or 1).
  int Options::*integer = nullptr;
  double Options::*real = nullptr;
  std::vector<double> Options::*list = nullptr;  // kReal: a list
  uint64_t Options::*seed = nullptr;
  int (*get)(const Options&) = nullptr;
  void (*set)(Options&, int) = nullptr;

  // The value as IsValid compares it with the range (kInteger, kReal).
  double Number(const Options& o) const {
    if (integer) return o.*integer;
    if (real) return o.*real;
    return 0;
  }
};

// "field: value: constraint", IsValid's message (as Ceres' Options::IsValid words it).
std::string OptionViolation(const std::string& field, double value, const std::string& constraint);

// False, with OptionViolation in *error, at the first value outside its
// entry's range (a list's items named "key[i]").
template <class Options>
bool RangesHold(const std::vector<OptionEntry<Options>>& table, const Options& o, std::string* error) {
  for (const OptionEntry<Options>& e : table) {
    if (!e.has_range || e.kind == OptionKind::kConfig) continue;  // kConfig: its consumers check it
    if (e.list) {
      const std::vector<double>& items = o.*e.list;
      for (size_t i = 0; i < items.size(); ++i)
        if (!e.range.Contains(items[i])) {
          *error = OptionViolation(e.key + "[" + std::to_string(i) + "]", items[i], e.Constraint());
          return false;
        }
    } else if (!e.range.Contains(e.Number(o))) {
      *error = OptionViolation(e.key, e.Number(o), e.Constraint());
      return false;
    }
  }
  return true;
}

// The entries as what every table says of them (for the reference's rows).
template <class Options>
std::vector<const OptionSpec*> OptionSpecs(const std::vector<OptionEntry<Options>>& table) {
  std::vector<const OptionSpec*> out;
  for (const OptionEntry<Options>& e : table) out.push_back(&e);
  return out;
}

// The entry of `key`, or nullptr.
template <class Options>
const OptionEntry<Options>* FindOption(const std::vector<OptionEntry<Options>>& table, const std::string& key) {
  for (const OptionEntry<Options>& e : table)
    if (e.key == key) return &e;
  return nullptr;
}

}  // namespace layerlab
