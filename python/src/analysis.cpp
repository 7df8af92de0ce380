// run(scene, out): the main job of `layerlab run` (analysis/run_pipeline.h),
// the same library call the command makes; contrast(scenes, section): the
// accommodation sweep of Fig. 5 (analysis/contrast.h) as arrays.
#include <optional>
#include <string>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "analysis/contrast.h"
#include "analysis/run_config.h"
#include "analysis/run_pipeline.h"
#include "python/src/bindings.h"
#include "python/src/json_convert.h"
#include "python/src/path_arg.h"
#include "systems/compile.h"

namespace py = pybind11;

namespace layerlab::python {
namespace {

py::array_t<double> Array(const std::vector<double>& v) { return py::array_t<double>(v.size(), v.data()); }

// The displays of the first scene file and the others; the options are those
// of a run section's "contrast" object (docs/run-section.md), read by the same
// reader with the same checks: `section`, or else the first scene's own.
py::list Contrast(const py::object& scenes, const py::object& section) {
  std::vector<std::string> files;
  if (py::isinstance<py::str>(scenes) || py::hasattr(scenes, "__fspath__")) {
    files.push_back(PathArg(scenes));
  } else {
    for (const py::handle& f : scenes) files.push_back(PathArg(f));
  }
  if (files.empty()) throw py::value_error("contrast: no scene");
  nlohmann::json given;
  if (!section.is_none()) given = {{"run", {{"contrast", ToJson(section)}}}};
  std::vector<ContrastCurve> curves;
  {
    py::gil_scoped_release release;
    std::vector<ContrastDisplay> displays;
    for (const std::string& f : files) displays.push_back(LoadContrastDisplay(f));
    Scene options;  // the options alone, named "contrast()" in errors (pointers /run/contrast/...)
    if (given.is_null()) {
      options = LoadScene(files.front());
      if (!options.document.contains("run") || !options.document["run"].contains("contrast"))
        options.document["run"] = {{"contrast", nlohmann::json::object()}};
    } else {
      options.file = "contrast()";
      options.document = given;
    }
    const ContrastRunConfig config = ReadRunConfig(options, displays.front().system).contrast;
    for (const std::string& f : config.scenes) displays.push_back(LoadContrastDisplay(f));
    curves = RunContrast(displays, config.options);
  }
  py::list list;
  for (const ContrastCurve& c : curves) {
    py::dict d;
    d["display"] = c.display, d["convention"] = c.convention, d["solver"] = c.solver;
    d["target_diopters"] = c.target_diopters, d["frequency"] = c.frequency;
    d["accommodation"] = Array(c.accommodation), d["contrast"] = Array(c.contrast);
    d["contrast_shifted"] = Array(c.contrast_shifted);
    d["peak"] = c.estimate.at, d["peak_uncertainty"] = c.estimate.uncertainty, d["flat"] = c.estimate.flat;
    d["at_target"] = c.at_target, d["psnr_db"] = c.psnr_db;
    d["solve_seconds"] = c.solve_seconds, d["sweep_seconds"] = c.sweep_seconds;
    list.append(d);
  }
  return list;
}

}  // namespace

void BindAnalysis(py::module_& m) {
  m.def(
      "run",
      [](const py::object& scene, const py::object& out, std::optional<int> iterations, std::optional<int> threads) {
        RunRequest request{.scene = PathArg(scene), .out = PathArg(out), .iterations = iterations, .threads = threads};
        RunOutcome outcome;
        {
          py::gil_scoped_release release;
          outcome = RunPipeline(request);
        }
        py::dict d;
        d["written"] = outcome.written;
        d["removed"] = outcome.removed;
        d["recovered"] = outcome.recovered;
        d["warnings"] = outcome.warnings;
        d["solved"] = outcome.solved;
        d["compare_table"] = outcome.compare_table;
        d["index_html"] = outcome.index_html;
        if (outcome.solved) {
          d["psnr_db"] = outcome.report.final_psnr_db;
          d["solver"] = outcome.report.solver;
          d["iterations"] = outcome.report.iterations;
          d["seconds"] = outcome.report.seconds;
        }
        return d;
      },
      py::arg("scene"), py::arg("out"), py::kw_only(), py::arg("iterations") = py::none(),
      py::arg("threads") = py::none(),
      "Runs the scene's \"solve\" and \"run\" sections like `layerlab run SCENE --out OUT`; returns what was written");
  m.def("contrast", &Contrast, py::arg("scenes"), py::arg("section") = py::none(),
        "Normalized contrast against accommodation (Fig. 5): one dict per display, depth and frequency, with "
        "\"natural\" for natural viewing; `section` is a run section's \"contrast\" object (default: the first "
        "scene's)");
}

}  // namespace layerlab::python
