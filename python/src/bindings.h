// The parts of the Python module (_layerlab), one file each; module.cpp calls them in order.
#pragma once

#include <pybind11/pybind11.h>

namespace layerlab::python {

void BindErrors(pybind11::module_& m);      // errors.cpp
void BindScene(pybind11::module_& m);       // scene.cpp: load_scene, compile, the display system
void BindLightField(pybind11::module_& m);  // lightfield.cpp: geometry, light fields, NumPy views
void BindSolve(pybind11::module_& m);       // solve.cpp: solve, its solution and report
void BindAnalysis(pybind11::module_& m);    // analysis.cpp: run, contrast
void BindCompare(pybind11::module_& m);     // compare.cpp: compare
void BindFit(pybind11::module_& m);         // fit.cpp (Ceres builds) or fit_missing.cpp: fit
void BindMetrics(pybind11::module_& m);     // metrics.cpp: ssim, ms_ssim, csf_jnd
void BindVerbosity(pybind11::module_& m);   // verbosity.cpp: set_verbosity, verbosity
void BindSrgb(pybind11::module_& m);        // srgb.cpp: srgb
void BindOperators(pybind11::module_& m);   // operators.cpp: DisplayOperator, RetinaOperator

}  // namespace layerlab::python
