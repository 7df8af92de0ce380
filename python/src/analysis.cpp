// run(scene, out): the main job of `layerlab run` (analysis/run_pipeline.h),
// the same library call the command makes.
#include <optional>
#include <string>

#include <pybind11/stl.h>

#include "analysis/run_pipeline.h"
#include "python/src/bindings.h"
#include "python/src/path_arg.h"

namespace py = pybind11;

namespace layerlab::python {

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
}

}  // namespace layerlab::python
