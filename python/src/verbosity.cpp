// layerlab.set_verbosity / layerlab.verbosity: how much the C++ core says on
// stderr (framework/progress.h), as the command line's -q and -v set it.
// Errors and warnings are never silenced.
#include <string>

#include "layerlab/framework/progress.h"
#include "layerlab/python/src/bindings.h"

namespace py = pybind11;

namespace layerlab::python {
namespace {

const char* Name(Verbosity v) {
  switch (v) {
    case Verbosity::kQuiet:
      return "quiet";
    case Verbosity::kVerbose:
      return "verbose";
    default:
      return "normal";
  }
}

}  // namespace

void BindVerbosity(py::module_& m) {
  m.def(
      "set_verbosity",
      [](const py::object& level) {
        if (!py::isinstance<py::str>(level))
          throw py::type_error("set_verbosity: level must be a str (\"quiet\", \"normal\" or \"verbose\"), not " +
                               std::string(py::str(level.get_type().attr("__name__"))));
        const std::string name = level.cast<std::string>();
        if (name == "quiet")
          SetVerbosity(Verbosity::kQuiet);
        else if (name == "normal")
          SetVerbosity(Verbosity::kNormal);
        else if (name == "verbose")
          SetVerbosity(Verbosity::kVerbose);
        else
          throw py::value_error("set_verbosity: level \"" + name +
                                "\" is not one of \"quiet\", \"normal\", \"verbose\"");
      },
      py::arg("level"),
      "How much layerlab says on stderr: \"quiet\" (progress and notes silenced; errors and warnings remain), "
      "\"normal\" (the default: a line per step) or \"verbose\" (every iteration of every run), for the whole "
      "process, as the command line's -q and -v.");
  m.def(
      "verbosity", [] { return std::string(Name(CurrentVerbosity())); },
      "The level set_verbosity set: \"quiet\", \"normal\" or \"verbose\".");
}

}  // namespace layerlab::python
