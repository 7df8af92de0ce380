// Bash and zsh completion scripts from the catalogue: command names, each
// command's options, the choices of an option that has them, and file names
// for every other value and positional.
#include <string>

#include "layerlab/app/cli_catalogue.h"

namespace layerlab::app {
namespace {

std::string Joined(const std::vector<std::string>& words, const std::string& separator = " ") {
  std::string out;
  for (const std::string& w : words) out += (out.empty() ? "" : separator) + w;
  return out;
}

std::vector<std::string> OptionNames(const CliCommand& c) {
  std::vector<std::string> names;
  for (const CliOption& o : c.options)
    if (!o.positional) names.insert(names.end(), o.names.begin(), o.names.end());
  return names;
}

std::vector<std::string> CommandNames(const std::vector<CliCommand>& catalogue) {
  std::vector<std::string> names;
  for (size_t k = 1; k < catalogue.size(); ++k) names.push_back(catalogue[k].name);
  return names;
}

// A zsh single-quoted word's body, and the brackets of an _arguments description escaped.
std::string ZshText(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '\'')
      out += "'\\''";
    else if (c == '[' || c == ']' || c == ':' || c == '\\')
      out += std::string("\\") + c;
    else if (c == '\n')
      out += ' ';
    else
      out += c;
  }
  return out;
}

std::string BashCommandCase(const CliCommand& c, const std::vector<std::string>& commands) {
  std::string out = "    " + c.name + ")\n      case \"$prev\" in\n";
  for (const CliOption& o : c.options)
    if (!o.positional && o.takes_value)
      out += "        " + Joined(o.names, "|") + ") COMPREPLY=($(compgen " +
             (o.choices.empty() ? std::string("-f") : "-W \"" + Joined(o.choices) + "\"") +
             " -- \"$cur\")); return ;;\n";
  out += "      esac\n";
  const std::string positional = c.name == "help" ? "-W \"" + Joined(commands) + "\"" : std::string("-f");
  out += "      if [[ \"$cur\" == -* ]]; then COMPREPLY=($(compgen -W \"" + Joined(OptionNames(c)) +
         "\" -- \"$cur\")); else COMPREPLY=($(compgen " + positional + " -- \"$cur\")); fi ;;\n";
  return out;
}

std::string ZshSpec(const CliOption& o) {
  const std::string help = "[" + ZshText(o.help) + "]";
  std::string action;
  if (o.takes_value) action = o.choices.empty() ? ":value:_files" : ":value:(" + ZshText(Joined(o.choices)) + ")";
  if (o.names.size() == 1) return "'" + o.names[0] + help + action + "'";
  return "'(" + Joined(o.names) + ")'{" + Joined(o.names, ",") + "}'" + help + action + "'";
}

}  // namespace

std::string BashCompletion(const std::vector<CliCommand>& catalogue) {
  const std::vector<std::string> commands = CommandNames(catalogue);
  std::string out =
      "# bash completion for layerlab; written by `layerlab help --completion bash` (docs/cli.md).\n"
      "_layerlab() {\n"
      "  local cur=\"${COMP_WORDS[COMP_CWORD]}\" prev=\"${COMP_WORDS[COMP_CWORD-1]}\" cmd=\"\" i\n"
      "  for ((i = 1; i < COMP_CWORD; i++)); do\n"
      "    case \"${COMP_WORDS[i]}\" in -*) ;; *) cmd=\"${COMP_WORDS[i]}\"; break ;; esac\n"
      "  done\n"
      "  case \"$cmd\" in\n"
      "    \"\") COMPREPLY=($(compgen -W \"" +
      Joined(commands) + " " + Joined(OptionNames(catalogue[0])) + "\" -- \"$cur\")) ;;\n";
  for (size_t k = 1; k < catalogue.size(); ++k) out += BashCommandCase(catalogue[k], commands);
  out += "  esac\n}\ncomplete -o filenames -F _layerlab layerlab\n";
  return out;
}

std::string ZshCompletion(const std::vector<CliCommand>& catalogue) {
  std::string out =
      "#compdef layerlab\n# zsh completion for layerlab; written by `layerlab help --completion zsh` (docs/cli.md).\n"
      "_layerlab() {\n  local curcontext=\"$curcontext\" state line\n  local -a commands\n  commands=(\n";
  for (size_t k = 1; k < catalogue.size(); ++k)
    out += "    '" + catalogue[k].name + ":" + ZshText(catalogue[k].description) + "'\n";
  out += "  )\n  _arguments -C \\\n";
  for (const CliOption& o : catalogue[0].options)
    if (!o.positional) out += "    " + ZshSpec(o) + " \\\n";
  out +=
      "    '1:command:->command' '*::argument:->argument'\n  case $state in\n"
      "    command) _describe -t commands 'layerlab command' commands ;;\n"
      "    argument)\n      case $line[1] in\n";
  for (size_t k = 1; k < catalogue.size(); ++k) {
    out += "        " + catalogue[k].name + ") _arguments";
    for (const CliOption& o : catalogue[k].options)
      if (!o.positional) out += " \\\n            " + ZshSpec(o);
    out += catalogue[k].name == "help" ? " \\\n            '1:command:(" + Joined(CommandNames(catalogue)) + ")' ;;\n"
                                       : " \\\n            '*:file:_files' ;;\n";
  }
  out += "      esac ;;\n  esac\n}\n_layerlab \"$@\"\n";
  return out;
}

}  // namespace layerlab::app
