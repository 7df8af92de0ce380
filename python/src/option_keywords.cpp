#include "layerlab/python/src/option_keywords.h"

#include "layerlab/framework/params.h"

namespace layerlab::python {

std::string KeywordDoc(const std::vector<const OptionSpec*>& entries) {
  std::string d;
  for (const OptionSpec* e : entries) {
    d += "  " + e->python + ": " + e->meaning;
    if (e->has_range) d += "; in " + e->range.Text(e->kind == OptionKind::kInteger);
    if (!e->choices.empty()) d += "; " + e->ChoiceList();
    d += " (default: " + e->default_text + ")\n";
  }
  return d;
}

const OptionSpec& KeywordEntry(const std::vector<const OptionSpec*>& entries, const std::string& name,
                               const std::string& function) {
  for (const OptionSpec* e : entries)
    if (e->python == name) return *e;
  std::vector<std::string> names;
  for (const OptionSpec* e : entries) names.push_back(e->python);
  throw pybind11::type_error(function + "() got an unexpected option '" + name +
                             "'; options: " + JoinWords(names, ", "));
}

}  // namespace layerlab::python
