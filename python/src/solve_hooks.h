// What a solve from Python looks at between iterations (the solve loop's
// `progress` and `interrupted` hooks, called while the GIL is released): the
// Python callback, whose true return value stops the solve, then pending
// signals (Ctrl-C). An exception of either is kept in `raised` and stops the
// solve; the caller raises it once the C++ solve has returned.
#pragma once

#include <functional>
#include <optional>
#include <utility>

#include <pybind11/pybind11.h>

#include "layerlab/solvers/solver.h"

namespace layerlab::python {

struct SolveHooks {
  bool stop = false;
  std::optional<pybind11::error_already_set> raised;

  // `row` makes the callback's argument (a dict) from the iteration's trace row.
  // The hooks refer to this object and to `callback`, which must outlive the
  // solve; they hold no Python reference, as the options are copied without the GIL.
  void Install(SolverOptions& o, const pybind11::object& callback,
               std::function<pybind11::dict(const IterationRecord&)> row) {
    callback_ = callback;
    row_ = std::move(row);
    if (!callback.is_none()) {
      o.progress = [this](const IterationRecord& r) {
        pybind11::gil_scoped_acquire acquire;
        try {
          if (pybind11::bool_(callback_(row_(r)))) stop = true;
        } catch (pybind11::error_already_set& e) {
          raised = std::move(e);
          stop = true;
        }
      };
    }
    o.interrupted = [this] {
      if (stop) return true;
      pybind11::gil_scoped_acquire acquire;
      if (PyErr_CheckSignals() != 0) {
        raised = pybind11::error_already_set();
        stop = true;
      }
      return stop;
    };
  }

 private:
  pybind11::handle callback_;
  std::function<pybind11::dict(const IterationRecord&)> row_;
};

}  // namespace layerlab::python
