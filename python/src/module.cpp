// The C++ half of the `layerlab` Python package (python/layerlab/__init__.py
// imports it); docs/python.md.
#include "layerlab/python/src/bindings.h"

PYBIND11_MODULE(_layerlab, m) {
  m.doc() = "layerlab: layered light-field displays (C++ core; use the layerlab package)";
  m.attr("__version__") = LAYERLAB_VERSION;
  layerlab::python::BindErrors(m);
  layerlab::python::BindScene(m);
  layerlab::python::BindLightField(m);
  layerlab::python::BindSolve(m);
  layerlab::python::BindAnalysis(m);
  layerlab::python::BindCompare(m);
  layerlab::python::BindFit(m);
  layerlab::python::BindMetrics(m);
  layerlab::python::BindVerbosity(m);
  layerlab::python::BindSrgb(m);
  layerlab::python::BindOperators(m);
}
