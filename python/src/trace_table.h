// A solve's trace (solvers/solver.h IterationRecord rows) as a dict of arrays:
// iteration, seconds, objective, psnr_db, focal_stack_psnr_db (NaN where the
// solve did not measure the focal stack); row 0 is the initial guess.
#pragma once

#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "layerlab/solvers/solver.h"

namespace layerlab::python {

inline pybind11::dict TraceTable(const std::vector<IterationRecord>& rows) {
  namespace py = pybind11;
  py::array_t<int> iteration(static_cast<py::ssize_t>(rows.size()));
  py::array_t<double> seconds(iteration.size()), objective(iteration.size()), psnr(iteration.size()),
      focal_stack(iteration.size());
  for (size_t i = 0; i < rows.size(); ++i) {
    iteration.mutable_at(i) = rows[i].iteration;
    seconds.mutable_at(i) = rows[i].seconds;
    objective.mutable_at(i) = rows[i].objective;
    psnr.mutable_at(i) = rows[i].psnr_db;
    focal_stack.mutable_at(i) = rows[i].focal_stack_psnr_db;
  }
  py::dict trace;
  trace["iteration"] = iteration, trace["seconds"] = seconds, trace["objective"] = objective, trace["psnr_db"] = psnr;
  trace["focal_stack_psnr_db"] = focal_stack;
  return trace;
}

// One row as the solve callback sees it.
inline pybind11::dict TraceRow(const IterationRecord& row) {
  pybind11::dict d;
  d["iteration"] = row.iteration, d["seconds"] = row.seconds, d["objective"] = row.objective;
  d["psnr_db"] = row.psnr_db, d["focal_stack_psnr_db"] = row.focal_stack_psnr_db;
  return d;
}

}  // namespace layerlab::python
