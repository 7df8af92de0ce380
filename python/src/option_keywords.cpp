#include "layerlab/python/src/option_keywords.h"

#include "layerlab/framework/params.h"

namespace layerlab::python {

std::string KeywordDoc(const std::vector<const OptionSpec*>& entries) {
  std::string d;
  for (const OptionSpec* e : entries) {
    d += "  " + e->python + ": " + e->meaning;
    if (e->kind == OptionKind::kReal && !e->FieldUnit().empty()) d += " (" + e->FieldUnit() + ")";
    if (e->has_range) d += "; in " + e->range.Text(e->kind == OptionKind::kInteger);
    if (!e->choices.empty()) d += "; " + e->ChoiceList();
    d += " (default: " + e->default_text + ")\n";
  }
  return d;
}

pybind11::list KeywordSignature(const std::vector<const OptionSpec*>& entries) {
  pybind11::list out;
  for (const OptionSpec* e : entries) {
    const char* annotation = "object";
    switch (e->kind) {
      case OptionKind::kInteger:
      case OptionKind::kSeed:
        annotation = "int";
        break;
      case OptionKind::kReal:
        annotation = e->type.rfind("array", 0) == 0 ? "list" : "float";  // "array of depths": a list of them
        break;
      case OptionKind::kChoice:
        annotation = "str";
        break;
      case OptionKind::kBoolean:
        annotation = "bool";
        break;
      case OptionKind::kConfig:
        break;
    }
    out.append(pybind11::make_tuple(e->python, annotation, e->default_text));
  }
  return out;
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
