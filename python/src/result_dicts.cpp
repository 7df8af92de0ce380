#include "layerlab/python/src/result_dicts.h"

#include <cmath>
#include <limits>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "layerlab/python/src/json_convert.h"
#include "layerlab/python/src/trace_table.h"
#include "layerlab/solvers/solution_writer.h"
#include "layerlab/solvers/trace_columns.h"

namespace py = pybind11;

namespace layerlab::python {
namespace {

py::array_t<double> Array(const std::vector<double>& v) { return py::array_t<double>(v.size(), v.data()); }

}  // namespace

py::dict ReportDict(const SolverReport& r) {
  py::dict d = FromJson(ReportToJson(r));
  d["final_psnr_db"] = r.final_psnr_db;  // +inf for a perfect fit (JSON has no infinity)
  d["trace"] = TraceTable(r.trace);
  return d;
}

py::dict CurveDict(const ContrastCurve& c) {
  py::dict d;
  d["display"] = c.display, d["convention"] = c.convention, d["solver"] = c.solver;
  d["factorized_for"] = c.factorized_for.empty() ? py::object(py::none()) : py::str(c.factorized_for);
  d["target_diopters"] = c.target_diopters, d["frequency"] = c.frequency;
  d["accommodation"] = Array(c.accommodation), d["contrast"] = Array(c.contrast);
  d["contrast_shifted"] = Array(c.contrast_shifted);
  d["peak"] = c.estimate.at, d["peak_uncertainty"] = c.estimate.uncertainty, d["flat"] = c.estimate.flat;
  d["at_target"] = c.at_target, d["psnr_db"] = c.psnr_db;
  d["solve_seconds"] = c.solve_seconds, d["sweep_seconds"] = c.sweep_seconds;
  // Seen from the eye's pupil moved by this (m: contrast's eyebox_range), or None; a binocular eye's vergence.
  d["pupil_moved_m"] =
      c.pupil_moved ? py::object(py::make_tuple(c.pupil_moved_m[0], c.pupil_moved_m[1])) : py::object(py::none());
  d["vergence_diopters"] = std::isnan(c.vergence_diopters) ? py::object(py::none()) : py::float_(c.vergence_diopters);
  return d;
}

py::dict CompareColumns(const std::vector<std::string>& scenes, const std::vector<CompareResult>& results,
                        const std::vector<std::string>& skipped, const std::vector<std::string>& warnings) {
  const auto n = static_cast<py::ssize_t>(results.size());
  py::list scene, display, solver, objective, options_from, termination, message, traces;
  py::array_t<double> psnr(n), focal_stack(n), seconds(n), refresh(n), luminance(n), efficiency({n, py::ssize_t{3}});
  py::array_t<int> iterations(n), subframes(n);
  py::array_t<double> flicker_visibility(n), flicker_hz(n);
  py::list flicker_visible;  // True, False, or None for a display of one subframe
  for (py::ssize_t i = 0; i < n; ++i) {
    const CompareResult& r = results[i];
    const std::optional<FlickerVerdict>& f = r.report.flicker;
    flicker_visibility.mutable_at(i) = f ? f->visibility : std::numeric_limits<double>::quiet_NaN();
    flicker_hz.mutable_at(i) = f ? f->frequency_hz : std::numeric_limits<double>::quiet_NaN();
    flicker_visible.append(f ? py::object(py::bool_(f->visible())) : py::object(py::none()));
    scene.append(scenes.at(i)), display.append(r.display), solver.append(r.solver);
    objective.append(r.report.objective);
    focal_stack.mutable_at(i) = FinalFocalStackPsnr(r.report);
    options_from.append(r.options_from);
    termination.append(ToString(r.report.termination)), message.append(r.report.message);
    psnr.mutable_at(i) = r.report.final_psnr_db, seconds.mutable_at(i) = r.report.seconds;
    iterations.mutable_at(i) = r.report.iterations, subframes.mutable_at(i) = r.subframes;
    refresh.mutable_at(i) = r.panel_refresh_hz, luminance.mutable_at(i) = r.luminance_efficiency;
    for (int c = 0; c < 3; ++c) efficiency.mutable_at(i, c) = r.brightness_efficiency[c];
    traces.append(TraceTable(r.report.trace));
  }
  py::dict d;
  d["scene"] = scene, d["display"] = display, d["solver"] = solver, d["objective"] = objective;
  d["final_psnr_db"] = psnr, d["final_focal_stack_psnr_db"] = focal_stack, d["seconds"] = seconds,
  d["iterations"] = iterations, d["subframes"] = subframes;
  d["panel_refresh_hz"] = refresh, d["luminance_efficiency"] = luminance, d["efficiency"] = efficiency;
  d["termination"] = termination, d["solver_options"] = options_from, d["message"] = message, d["trace"] = traces;
  d["flicker_visible"] = flicker_visible, d["flicker_visibility"] = flicker_visibility, d["flicker_hz"] = flicker_hz;
  for (const TraceColumn* c : MeasuredMetricColumns(results)) {  // final_focal_stack_ssim, ...: as compare.csv
    py::array_t<double> values(n);
    for (py::ssize_t i = 0; i < n; ++i) values.mutable_at(i) = FinalTraceValue(*c, results[i].report);
    d[py::str(std::string("final_") + c->name)] = values;
  }
  d["skipped"] = skipped, d["warnings"] = warnings;
  d["table"] = CompareTable(results);
  return d;
}

}  // namespace layerlab::python
