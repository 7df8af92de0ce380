#include "layerlab/app/option_flags.h"

#include "layerlab/app/number_list.h"
#include "layerlab/framework/error.h"

namespace layerlab::app {
namespace {

// Quantities other than fractions are read as text, with their unit.
bool AsText(const OptionSpec& e) { return e.dimension != Dimension::kFraction; }

OptionUnit UnitOf(const OptionSpec& e) { return {e.dimension, e.FieldUnit()}; }

}  // namespace

void AddOptionFlag(CLI::App* cmd, const OptionSpec& e, OptionFlags& flags, bool with_default, bool list) {
  // A switch says what it does; the others their default.
  const bool say_default = with_default && e.kind != OptionKind::kBoolean;
  const std::string help = say_default ? e.cli_help + " (default " + e.default_text + ")" : e.cli_help;
  switch (e.kind) {
    case OptionKind::kInteger:
      cmd->add_option(e.cli_flag, flags.integers[e.key], help);
      break;
    case OptionKind::kReal:
      if (AsText(e) || list)
        cmd->add_option(e.cli_flag, flags.texts[e.key], help);
      else
        cmd->add_option(e.cli_flag, flags.reals[e.key], help);
      break;
    case OptionKind::kChoice:
      cmd->add_option(e.cli_flag, flags.texts[e.key], help);
      break;
    case OptionKind::kBoolean:
      cmd->add_flag(e.cli_flag, flags.switches[e.key], help);
      break;
    case OptionKind::kSeed:
    case OptionKind::kConfig:
      throw Error("option " + e.key + ": no command-line flag of this kind");
  }
}

std::optional<double> GivenReal(const OptionFlags& flags, const OptionSpec& e) {
  if (!AsText(e)) return flags.reals.at(e.key);
  const std::string& text = flags.texts.at(e.key);
  if (text.empty()) return std::nullopt;
  return ParseOptionValue(text, e.cli_flag, UnitOf(e));
}

std::optional<std::vector<double>> GivenList(const OptionFlags& flags, const OptionSpec& e) {
  const std::string& text = flags.texts.at(e.key);
  if (text.empty()) return std::nullopt;
  return ParseNumberList(text, e.cli_flag, UnitOf(e), e.dimension == Dimension::kOpticalPower);
}

int GivenChoice(const OptionFlags& flags, const OptionSpec& e) {
  const std::string& text = flags.texts.at(e.key);
  if (text.empty()) return -1;
  const int index = e.ChoiceIndex(text);
  if (index < 0) throw Error(e.cli_flag + ": \"" + text + "\" is not one of " + e.ChoiceList());
  return index;
}

bool WasGiven(const OptionFlags& flags, const OptionSpec& e) {
  if (const auto i = flags.integers.find(e.key); i != flags.integers.end() && i->second) return true;
  if (const auto r = flags.reals.find(e.key); r != flags.reals.end() && r->second) return true;
  if (const auto t = flags.texts.find(e.key); t != flags.texts.end() && !t->second.empty()) return true;
  const auto b = flags.switches.find(e.key);
  return b != flags.switches.end() && b->second;
}

}  // namespace layerlab::app
