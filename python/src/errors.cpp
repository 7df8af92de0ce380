// layerlab::Error becomes layerlab.Error, or layerlab.SceneError when it names
// a place in an input file (file and JSON pointer); both are defined in
// python/layerlab/errors.py so that they are plain Python classes.
#include <exception>

#include "layerlab/framework/error.h"
#include "layerlab/python/src/bindings.h"

namespace py = pybind11;

namespace layerlab::python {

void BindErrors(py::module_& m) {
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const Error& e) {
      const bool located = !e.where().file.empty() || !e.where().pointer.empty();
      py::object type = py::module_::import("layerlab.errors").attr(located ? "SceneError" : "Error");
      py::object value = type(e.what(), e.where().file, e.where().pointer, e.message());
      PyErr_SetObject(type.ptr(), value.ptr());
    }
  });
}

}  // namespace layerlab::python
