// A path argument: a str or any os.PathLike (pathlib.Path), as os.fspath takes it.
#pragma once

#include <string>

#include <pybind11/pybind11.h>

namespace layerlab::python {

inline std::string PathArg(const pybind11::handle& path) {
  return pybind11::module_::import("os").attr("fspath")(path).cast<std::string>();
}

}  // namespace layerlab::python
