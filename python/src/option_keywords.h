// Python keyword arguments made from an option table
// (framework/option_table.h): each entry's Python name, checked for its type
// here (TypeError, or ArgumentError naming the choices) and for its range by
// the options' IsValid; the docstring's lines from the same entries.
#pragma once

#include <limits>
#include <string>
#include <vector>

#include <pybind11/pybind11.h>

#include "layerlab/framework/option_table.h"
#include "layerlab/python/src/arguments.h"

namespace layerlab::python {

// "  name: meaning (unit); in [a, b]; a or b (default: ...)\n" for each entry, the unit a real's (SI, or the
// entry's own: "deg").
std::string KeywordDoc(const std::vector<const OptionSpec*>& entries);

// [(name, annotation, default)] for each entry: the keyword-only parameters
// python/layerlab/__init__.py spells out in the signature of the function
// that takes them ("int", "float", "list" (of reals), "bool", "str", "object";
// the default as the reference gives it).
pybind11::list KeywordSignature(const std::vector<const OptionSpec*>& entries);

// The entry whose Python name is `name`; else raises TypeError "<function>()
// got an unexpected option 'name'; options: a, b, ...".
const OptionSpec& KeywordEntry(const std::vector<const OptionSpec*>& entries, const std::string& name,
                               const std::string& function);

// The entries of `table` with a Python name, kConfig ones only when `with_config`.
template <class Options>
std::vector<const OptionSpec*> KeywordEntries(const std::vector<OptionEntry<Options>>& table, bool with_config) {
  std::vector<const OptionSpec*> out;
  for (const OptionEntry<Options>& e : table)
    if (!e.python.empty() && (with_config || e.kind != OptionKind::kConfig)) out.push_back(&e);
  return out;
}

// `value` into e's field of `o` (not kConfig, not a list: a list is read as the scene reads it).
template <class Options>
void SetKeyword(Options& o, const OptionEntry<Options>& e, const pybind11::handle& value) {
  namespace py = pybind11;
  const std::string& key = e.python;
  switch (e.kind) {
    case OptionKind::kInteger:
      o.*e.integer = static_cast<int>(
          IntegerArg(value, key, std::numeric_limits<int>::min(), std::numeric_limits<int>::max(), e.Constraint()));
      break;
    case OptionKind::kReal:
      if (e.real) o.*e.real = RealArg(value, key);
      break;
    case OptionKind::kSeed:
      o.*e.seed = Unsigned64Arg(value, key);
      break;
    case OptionKind::kChoice: {
      if (!py::isinstance<py::str>(value))
        throw py::type_error(key + ": expected a str (" + e.ChoiceList() + "), got " + TypeName(value));
      const std::string v = value.cast<std::string>();
      const int index = e.ChoiceIndex(v);
      if (index < 0) RaiseArgumentError(key + ": \"" + v + "\" is not one of " + e.ChoiceList());
      e.set(o, index);
      break;
    }
    case OptionKind::kBoolean:
      if (!PyBool_Check(value.ptr())) throw py::type_error(key + ": expected a bool, got " + TypeName(value));
      e.set(o, value.cast<bool>() ? 1 : 0);
      break;
    case OptionKind::kConfig:
      break;
  }
}

}  // namespace layerlab::python
