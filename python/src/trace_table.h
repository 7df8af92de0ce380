// A solve's trace (solvers/solver.h IterationRecord rows) as a dict of
// arrays, one per column of solvers/trace_columns.h (NaN where the solve did
// not measure it); row 0 is the initial guess.
#pragma once

#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "layerlab/solvers/solver.h"
#include "layerlab/solvers/trace_columns.h"

namespace layerlab::python {

inline pybind11::dict TraceTable(const std::vector<IterationRecord>& rows) {
  namespace py = pybind11;
  py::dict trace;
  const auto n = static_cast<py::ssize_t>(rows.size());
  for (const TraceColumn& c : TraceColumns()) {
    if (c.kind == TraceValueKind::kCount) {
      py::array_t<int> column(n);
      for (py::ssize_t i = 0; i < n; ++i) column.mutable_at(i) = static_cast<int>(c.value(rows[i]));
      trace[c.name] = column;
    } else {
      py::array_t<double> column(n);
      for (py::ssize_t i = 0; i < n; ++i) column.mutable_at(i) = c.value(rows[i]);
      trace[c.name] = column;
    }
  }
  return trace;
}

// One row as the solve callback sees it.
inline pybind11::dict TraceRow(const IterationRecord& row) {
  pybind11::dict d;
  for (const TraceColumn& c : TraceColumns()) {
    if (c.kind == TraceValueKind::kCount)
      d[c.name] = static_cast<int>(c.value(row));
    else
      d[c.name] = c.value(row);
  }
  return d;
}

}  // namespace layerlab::python
