// compare(scenes, target, solvers=...): `layerlab compare` (analysis/compare.h,
// the same runs, like for like unless scene_options, the same solves and
// warnings) returning its table as columns, one row per display and solver,
// each with its trace.
#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "layerlab/analysis/compare.h"
#include "layerlab/analysis/target_source.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/lightfield_checks.h"
#include "layerlab/python/src/arguments.h"
#include "layerlab/python/src/bindings.h"
#include "layerlab/python/src/path_arg.h"
#include "layerlab/python/src/result_dicts.h"
#include "layerlab/python/src/solve_hooks.h"
#include "layerlab/python/src/trace_table.h"

namespace py = pybind11;

namespace layerlab::python {
namespace {

std::vector<std::string> PathList(const py::object& paths) {
  std::vector<std::string> files;
  if (py::isinstance<py::str>(paths) || py::hasattr(paths, "__fspath__")) return {PathArg(paths)};
  for (const py::handle& f : paths) files.push_back(PathArg(f));
  return files;
}

// None: each scene's own solver; "all"; a name; a list of names (`what` names the argument in a TypeError).
std::vector<std::string> SolverList(const py::object& solvers, const std::string& what) {
  if (solvers.is_none()) return {};
  if (py::isinstance<py::str>(solvers)) return {solvers.cast<std::string>()};
  if (!py::isinstance<py::sequence>(solvers))
    throw py::type_error(what + ": expected None, a str or a list of str, got " + TypeName(solvers));
  std::vector<std::string> names;
  size_t k = 0;
  for (const py::handle& name : solvers) {
    if (!py::isinstance<py::str>(name))
      throw py::type_error(what + "[" + std::to_string(k) + "]: expected a str, got " + TypeName(name) + " " +
                           Repr(name));
    names.push_back(name.cast<std::string>());
    ++k;
  }
  return names;
}

// fovea_deg=(x, y) degrees and jnd_exponent, checked; only with metrics.
MetricSettings MetricSettingsArgs(const py::object& fovea, const py::object& jnd_exponent, bool with_metrics) {
  MetricSettings settings;
  if (!fovea.is_none()) {
    const std::vector<double> gaze = RealListArg(fovea, "compare: fovea_deg");
    if (gaze.size() != 2) RaiseArgumentError("compare: fovea_deg: give (x, y) in degrees");
    settings.fovea_deg = std::array<double, 2>{gaze[0], gaze[1]};
  }
  if (!jnd_exponent.is_none()) settings.jnd_minkowski_exponent = RealArg(jnd_exponent, "compare: jnd_exponent");
  CheckArgument([&] { CheckMetricSettings(settings, "compare: jnd_exponent", "compare: fovea_deg"); });
  if ((!fovea.is_none() || !jnd_exponent.is_none()) && !with_metrics)
    RaiseArgumentError(
        "compare: fovea_deg and jnd_exponent set how the focal stack's metrics are measured: give metrics");
  return settings;
}

py::dict Compare(const py::object& scenes, const py::object& target, const py::object& solvers,
                 const py::object& iterations_arg, const py::object& time_budget_arg, bool scene_options,
                 const py::object& objectives, const py::object& metrics, const py::object& fovea,
                 const py::object& jnd_exponent, const py::object& callback) {
  std::optional<int> iterations;
  std::optional<double> time_budget;
  if (!iterations_arg.is_none())
    iterations = static_cast<int>(IntegerArg(iterations_arg, "compare: iterations", 1, 1000000));
  if (!time_budget_arg.is_none()) time_budget = RealArg(time_budget_arg, "compare: time_budget");
  if (time_budget && !(*time_budget >= 0 && std::isfinite(*time_budget)))
    RaiseArgumentError("compare: time_budget must be 0 (none) or more seconds");
  const std::vector<std::string> files = PathList(scenes);
  if (files.empty()) throw py::value_error("compare: no scene");
  std::vector<ObjectiveKind> objective_kinds;
  for (const std::string& name : SolverList(objectives, "compare: objectives")) {  // None, a name or a list of names
    const std::optional<ObjectiveKind> k = ObjectiveKindNamed(name);
    if (!k) throw py::value_error("compare: objectives: \"" + name + "\" is not one of lightfield or retinal");
    objective_kinds.push_back(*k);
  }
  std::string metric_names;  // None, a name or a list of names
  for (const std::string& name : SolverList(metrics, "compare: metrics")) metric_names += "," + name;
  std::vector<const RetinalMetric*> metric_list;
  if (!metric_names.empty())
    CheckArgument([&] { metric_list = ParseRetinalMetrics(metric_names.substr(1), "compare: metrics"); });
  const MetricSettings settings = MetricSettingsArgs(fovea, jnd_exponent, !metric_list.empty());
  const CompareSelection selection{SolverList(solvers, "compare: solvers"),
                                   iterations,
                                   time_budget,
                                   scene_options,
                                   objective_kinds,
                                   metric_list,
                                   settings};
  std::shared_ptr<LightField> given;
  SolveConfig target_config;  // a light-field folder, or a target scene file rendered as --target-scene does
  if (py::isinstance<LightField>(target)) {
    given = target.cast<std::shared_ptr<LightField>>();
    CheckArgument([&] { CheckLightFieldValues(*given, "compare: target"); });  // as a folder's views are held to
  } else {
    const std::string path = PathArg(target);
    (std::filesystem::is_regular_file(path) ? target_config.target_scene : target_config.target) = path;
  }

  std::vector<std::string> skipped;
  std::vector<CompareRun> runs;
  std::unique_ptr<Target> loaded;
  {
    py::gil_scoped_release release;
    runs = CompareRunsOf(files, selection, &skipped);
    target_config.target_moved_m = CommonTargetMove(runs);
    if (!given) loaded = LoadOrRenderTarget(target_config, "target");
  }
  const LightField& lf = given ? *given : loaded->light_field;
  if (loaded)
    for (CompareRun& run : runs) AttachRetinalTarget(*loaded, &run.options);

  // One run at a time, so that a stop from the callback or Ctrl-C ends the comparison there.
  std::vector<CompareResult> results;
  SolveHooks hooks;
  for (CompareRun& run : runs) {
    const std::string display = run.display, solver = run.solver, objective = ToString(run.options.objective);
    hooks.Install(run.options, callback, [display, solver, objective](const IterationRecord& r) {
      py::dict d = TraceRow(r);
      d["display"] = display, d["solver"] = solver, d["objective_kind"] = objective;
      return d;
    });
    {
      py::gil_scoped_release release;
      results.push_back(RunComparison({run}, lf).front());
    }
    if (hooks.raised) throw std::move(*hooks.raised);
    const SolverReport& report = results.back().report;
    if (!report.IsSolutionUsable()) throw Error("compare: " + RunLabel(results.back()) + " failed: " + report.message);
    if (hooks.stop) break;
  }
  runs.resize(results.size());
  std::vector<std::string> scene_of_row;
  for (const CompareRun& run : runs) scene_of_row.push_back(run.system.file);
  return CompareColumns(scene_of_row, results, skipped, CompareWarnings(runs, results, lf.geometry));
}

}  // namespace

void BindCompare(py::module_& m) {
  m.def("compare", &Compare, py::arg("scenes"), py::arg("target"), py::kw_only(), py::arg("solvers") = py::none(),
        py::arg("iterations") = py::none(), py::arg("time_budget") = py::none(), py::arg("scene_options") = false,
        py::arg("objectives") = py::none(), py::arg("metrics") = py::none(), py::arg("fovea_deg") = py::none(),
        py::arg("jnd_exponent") = py::none(), py::arg("callback") = py::none(),
        "Several displays and solvers on one target (a LightField, a light-field folder or a target scene file), as "
        "`layerlab compare`: like for like (each solver's defaults) unless scene_options; objectives (\"lightfield\", "
        "\"retinal\" or a list) as --objectives; metrics (\"ssim\", \"ms_ssim\", \"jnd\", \"all\" or a list) as "
        "--metrics, weighted about a gaze fovea=(x, y) degrees and the JND pooled with jnd_exponent as --fovea and "
        "--jnd-exponent. A dict of columns, one row per display, solver and objective "
        "(scene, display, solver, objective, solver_options, final_psnr_db, final_focal_stack_psnr_db, seconds, "
        "iterations, subframes, panel_refresh_hz, luminance_efficiency, efficiency, termination, message, "
        "flicker_visible, flicker_visibility, flicker_hz (NaN for a display of one subframe), trace), with "
        "skipped, warnings and table");
}

}  // namespace layerlab::python
