#include "layerlab/app/cli_catalogue.h"

#include <CLI/CLI.hpp>

namespace layerlab::app {
namespace {

// CLI11's "TEXT:{none,mtf,wave}" -> {none, mtf, wave}.
std::vector<std::string> ChoicesOf(const std::string& type_name) {
  const size_t open = type_name.find(":{"), close = type_name.rfind('}');
  if (open == std::string::npos || close == std::string::npos || close < open) return {};
  std::vector<std::string> choices;
  std::string item;
  for (size_t k = open + 2; k <= close; ++k) {
    if (k == close || type_name[k] == ',') {
      if (!item.empty()) choices.push_back(item);
      item.clear();
    } else {
      item += type_name[k];
    }
  }
  return choices;
}

CliOption OptionOf(const CLI::Option& o) {
  CliOption c;
  c.positional = !o.nonpositional();
  if (c.positional) {
    c.names = {o.get_name()};
  } else {
    for (const std::string& s : o.get_snames()) c.names.push_back("-" + s);
    for (const std::string& l : o.get_lnames()) c.names.push_back("--" + l);
  }
  c.takes_value = o.get_expected_max() != 0;  // a flag expects none
  c.required = o.get_required();
  c.repeatable = c.positional && o.get_items_expected_max() > 1;
  c.choices = ChoicesOf(o.get_type_name());
  c.help = o.get_description();
  return c;
}

CliCommand CommandOf(const CLI::App& app, const std::string& name) {
  CliCommand c{name, app.get_description(), {}};
  for (const CLI::Option* o : app.get_options())
    if (!o->get_group().empty()) c.options.push_back(OptionOf(*o));  // the hidden: renamed ones (renamed_options.h)
  return c;
}

}  // namespace

std::vector<CliCommand> Catalogue(const CLI::App& app) {
  std::vector<CliCommand> all{CommandOf(app, "layerlab")};
  for (const CLI::App* cmd : app.get_subcommands({})) all.push_back(CommandOf(*cmd, cmd->get_name()));
  return all;
}

nlohmann::json CatalogueJson(const std::vector<CliCommand>& catalogue) {
  nlohmann::json commands = nlohmann::json::array();
  for (const CliCommand& c : catalogue) {
    nlohmann::json options = nlohmann::json::array();
    for (const CliOption& o : c.options)
      options.push_back({{"names", o.names},
                         {"positional", o.positional},
                         {"takes_value", o.takes_value},
                         {"required", o.required},
                         {"repeatable", o.repeatable},
                         {"choices", o.choices},
                         {"help", o.help}});
    commands.push_back({{"name", c.name}, {"description", c.description}, {"options", options}});
  }
  return {{"commands", commands}};
}

}  // namespace layerlab::app
