// layerlab(1) from the catalogue, in the man(7) macros.
#include <string>

#include "layerlab/app/cli_catalogue.h"
#include "layerlab/app/exit_status.h"

namespace layerlab::app {
namespace {

// Text safe in roff: backslashes and hyphens escaped, no line starting with a control character.
std::string Roff(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '\\')
      out += "\\e";
    else if (c == '-')
      out += "\\-";
    else if (c == '\n')
      out += ' ';
    else
      out += c;
  }
  if (!out.empty() && (out[0] == '.' || out[0] == '\'')) out = "\\&" + out;
  return out;
}

std::string OptionLine(const CliOption& o) {
  std::string line;
  for (const std::string& n : o.names) line += (line.empty() ? "" : ", ") + ("\\fB" + Roff(n) + "\\fR");
  if (o.positional)
    line = "\\fI" + Roff(o.names[0]) + (o.repeatable ? "...\\fR" : "\\fR");
  else if (o.takes_value)
    line += o.choices.empty() ? " \\fIVALUE\\fR" : " \\fI" + Roff(o.choices[0]) + "|...\\fR";
  return line;
}

std::string OptionItems(const CliCommand& c) {
  std::string out;
  for (const CliOption& o : c.options) {
    out += ".TP\n" + OptionLine(o) + "\n" + Roff(o.help);
    if (o.required) out += " (required)";
    if (!o.choices.empty()) {
      std::string list;
      for (const std::string& choice : o.choices) list += (list.empty() ? "" : ", ") + choice;
      out += " One of: " + Roff(list) + ".";
    }
    out += "\n";
  }
  return out;
}

}  // namespace

std::string ManPage(const std::vector<CliCommand>& catalogue, const std::string& version) {
  std::string out = ".TH LAYERLAB 1 \"\" \"layerlab " + Roff(version) +
                    "\" \"User Commands\"\n"
                    ".SH NAME\nlayerlab \\- " +
                    Roff(catalogue[0].description.substr(catalogue[0].description.find(": ") + 2)) +
                    "\n.SH SYNOPSIS\n.B layerlab\n[\\fB\\-q\\fR|\\fB\\-v\\fR] [\\fB\\-\\-json\\fR] \\fICOMMAND\\fR "
                    "[\\fIARGUMENTS\\fR] [\\fIOPTIONS\\fR]\n"
                    ".br\n.B layerlab help\n[\\fICOMMAND\\fR]\n"
                    ".SH DESCRIPTION\nA display is one JSON file (its scene); each command reads scenes and "
                    "light-field folders and writes a folder of results with an index.html. The options of "
                    "the top level below may also be given after the command.\n";
  out += OptionItems(catalogue[0]);
  out += ".SH COMMANDS\n";
  for (size_t k = 1; k < catalogue.size(); ++k) {
    const CliCommand& c = catalogue[k];
    out += ".SS \"" + Roff(c.name) + "\"\n" + Roff(c.description) + "\n";
    out += OptionItems(c);
  }
  out += ".SH EXIT STATUS\n";
  for (const ExitStatusMeaning& e : kExitStatusMeanings)
    out += ".TP\n.B " + std::to_string(e.status) + "\n" + Roff(e.meaning) + "\n";
  out +=
      ".SH SEE ALSO\nThe documentation beside the sources: docs/cli.md (the options' vocabulary, the JSON "
      "results), docs/tutorial.md, docs/scene-reference.md.\n";
  return out;
}

}  // namespace layerlab::app
