// A command's flags made from an option table (framework/option_table.h):
// one flag per entry that names one, read as the scene reads the key (a
// quantity with a unit, or a bare number in the field's unit; a list
// comma-separated), and set over the options only when given. Entries of
// kind kConfig are the command's own to register and apply.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "layerlab/framework/option_table.h"

namespace layerlab::app {

// What was given, by option key. Registered in place: keep it where AddOptionFlag saw it.
struct OptionFlags {
  std::map<std::string, std::optional<int>> integers;
  std::map<std::string, std::optional<double>> reals;  // fractions, as CLI11 reads them (negative too)
  std::map<std::string, std::string> texts;            // choices, lists, and quantities with a unit ("2 min")
  std::map<std::string, bool> switches;
};

// The flag of `e` (not kConfig, not kSeed; `list`: of a list field); `with_default`: its help ends with the
// table's default.
void AddOptionFlag(CLI::App* cmd, const OptionSpec& e, OptionFlags& flags, bool with_default = false,
                   bool list = false);

// The value given for `e`'s flag, in its field's unit; nullopt when not given.
std::optional<double> GivenReal(const OptionFlags& flags, const OptionSpec& e);
std::optional<std::vector<double>> GivenList(const OptionFlags& flags, const OptionSpec& e);
// The index among e's choices given; -1 when not given. A name not among them is refused.
int GivenChoice(const OptionFlags& flags, const OptionSpec& e);

template <class Options>
void AddOptionFlags(CLI::App* cmd, const std::vector<OptionEntry<Options>>& table, OptionFlags& flags,
                    bool with_default = false) {
  for (const OptionEntry<Options>& e : table)
    if (!e.cli_flag.empty() && e.kind != OptionKind::kConfig)
      AddOptionFlag(cmd, e, flags, with_default, e.list != nullptr);
}

// Sets what was given over `o`; a value out of range is left to the options' IsValid.
template <class Options>
void ApplyOptionFlags(const OptionFlags& flags, const std::vector<OptionEntry<Options>>& table, Options& o) {
  for (const OptionEntry<Options>& e : table) {
    if (e.cli_flag.empty()) continue;
    switch (e.kind) {
      case OptionKind::kInteger:
        if (const std::optional<int>& v = flags.integers.at(e.key)) o.*e.integer = *v;
        break;
      case OptionKind::kReal:
        if (e.list) {
          if (std::optional<std::vector<double>> v = GivenList(flags, e)) o.*e.list = std::move(*v);
        } else if (const std::optional<double> v = GivenReal(flags, e)) {
          o.*e.real = *v;
        }
        break;
      case OptionKind::kChoice:
        if (const int index = GivenChoice(flags, e); index >= 0) e.set(o, index);
        break;
      case OptionKind::kBoolean:  // the flag says the opposite of the default
        if (flags.switches.at(e.key)) e.set(o, e.get(Options{}) ? 0 : 1);
        break;
      case OptionKind::kSeed:
      case OptionKind::kConfig:
        break;
    }
  }
}

// Whether `e`'s flag was given.
bool WasGiven(const OptionFlags& flags, const OptionSpec& e);

// IsValid's "field: value: constraint" with the field named by its flag
// ("--field: 0: ..."), as the command's user wrote it; with `given`, only
// when that flag was given (else the value came from the scene: its key).
template <class Options>
std::string NameTheFlag(const std::vector<OptionEntry<Options>>& table, const std::string& why,
                        const OptionFlags* given = nullptr) {
  for (const OptionEntry<Options>& e : table)
    if (!e.cli_flag.empty() && why.rfind(e.key, 0) == 0 && why.size() > e.key.size() &&
        (why[e.key.size()] == ':' || why[e.key.size()] == '[' || why[e.key.size()] == '.'))
      return !given || WasGiven(*given, e) ? e.cli_flag + why.substr(e.key.size()) : why;
  return why;
}

}  // namespace layerlab::app
