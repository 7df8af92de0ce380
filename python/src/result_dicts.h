// The library's results as Python dicts, one home for each, so that solve(),
// contrast(), compare() and run() return the same keys for the same thing.
#pragma once

#include <string>
#include <vector>

#include <pybind11/pybind11.h>

#include "layerlab/analysis/compare.h"
#include "layerlab/analysis/contrast.h"
#include "layerlab/solvers/solver.h"

namespace layerlab::python {

// A solve report (report.json's keys) with its trace as a dict of arrays.
pybind11::dict ReportDict(const SolverReport& report);

// One contrast curve: display, convention, solver, target_diopters, frequency,
// accommodation, contrast, contrast_shifted (arrays), peak, peak_uncertainty,
// flat, at_target, psnr_db, solve_seconds, sweep_seconds.
pybind11::dict CurveDict(const ContrastCurve& curve);

// A comparison as columns, one row per result (the names of compare.csv),
// `scenes` the scene file of each row, with skipped, warnings and table.
pybind11::dict CompareColumns(const std::vector<std::string>& scenes, const std::vector<CompareResult>& results,
                              const std::vector<std::string>& skipped, const std::vector<std::string>& warnings);

}  // namespace layerlab::python
