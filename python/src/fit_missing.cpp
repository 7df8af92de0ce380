// fit() in a build without Ceres (LAYERLAB_WITH_CERES=OFF): there, to say why it cannot.
#include "layerlab/framework/error.h"
#include "layerlab/python/src/bindings.h"

namespace py = pybind11;

namespace layerlab::python {

void BindFit(py::module_& m) {
  m.def(
      "fit",
      [](const py::args&, const py::kwargs&) -> py::object {
        throw Error("fit: calibration needs Ceres (this build has LAYERLAB_WITH_CERES=OFF)");
      },
      "Calibration needs Ceres, which this build left out");
}

}  // namespace layerlab::python
