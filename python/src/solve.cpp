// solve(system_or_scene, target, solver=..., callback=..., **options): the
// patterns as NumPy views of the solution's own buffers and the report with
// its trace. The GIL is released while the solver works; the callback and
// Ctrl-C are looked at between iterations (the solve loop's `progress` and
// `interrupted` hooks), so a stop keeps the last complete iteration.
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <optional>
#include <string>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "layerlab/analysis/retina_sweep.h"
#include "layerlab/analysis/solve_job.h"
#include "layerlab/analysis/target_source.h"
#include "layerlab/framework/lightfield_checks.h"
#include "layerlab/framework/params.h"
#include "layerlab/framework/units.h"
#include "layerlab/kernels/synthesis.h"
#include "layerlab/python/src/arguments.h"
#include "layerlab/python/src/bindings.h"
#include "layerlab/python/src/display_args.h"
#include "layerlab/python/src/json_convert.h"
#include "layerlab/python/src/numpy_view.h"
#include "layerlab/python/src/option_keywords.h"
#include "layerlab/python/src/path_arg.h"
#include "layerlab/python/src/result_dicts.h"
#include "layerlab/python/src/solve_hooks.h"
#include "layerlab/python/src/trace_table.h"
#include "layerlab/retina/eye_optics.h"
#include "layerlab/retina/lightfield_radiance.h"
#include "layerlab/retina/retina.h"
#include "layerlab/solvers/solution_writer.h"
#include "layerlab/solvers/solve_config.h"
#include "layerlab/solvers/solver_option_table.h"
#include "layerlab/systems/compile.h"
#include "layerlab/systems/layer_sampler.h"
#include "layerlab/systems/lc_response.h"
#include "layerlab/systems/source_spread.h"

namespace py = pybind11;

namespace layerlab::python {
namespace {

struct Solution {
  std::shared_ptr<DisplaySystem> system;
  std::shared_ptr<const DisplayModel> model;
  std::shared_ptr<LightField> target;
  std::string solver;
  Sampling sampling = Sampling::kNearest;  // how the layers (and the target, seen naturally) are read
  Patterns patterns;
  SolverReport report;
};

// The keywords of solve() beyond its parameters: the option table's Python
// names (solvers/solver_option_table.h), each checked for its type here and for
// its range by SolverOptions::IsValid.
const std::vector<const OptionSpec*>& OptionKeywords() {
  static const std::vector<const OptionSpec*> entries = KeywordEntries(SolverOptionTable(), false);
  return entries;
}

void SetOption(SolverOptions& o, const std::string& key, const py::handle& value) {
  SetKeyword(o, *FindSolverOption(KeywordEntry(OptionKeywords(), key, "solve").key), value);
}

// solve()'s docstring: what it does and every option keyword, from the table.
const char* SolveDoc() {
  static const std::string doc =
      "Factorizes a target light field into layer patterns (docs/python.md).\n\n"
      "solver: a solver's name (default: the scene's, or the display's default); sampling: nearest or bilinear.\n"
      "Options (keyword arguments; docs/scene-reference.md):\n" +
      KeywordDoc(OptionKeywords());
  return doc.c_str();
}

// The target, held to what a light-field folder's views are held to (finite,
// non-negative light; ReadLightField): the pixel that is not is named.
std::shared_ptr<LightField> TargetOf(const py::handle& target, const DisplaySystem& system) {
  std::shared_ptr<LightField> lf;
  if (py::isinstance<LightField>(target)) {
    lf = target.cast<std::shared_ptr<LightField>>();
  } else {
    // An array: the display's own geometry (display_geometry), copied once into a light field.
    lf = py::module_::import("layerlab._layerlab")
             .attr("LightField")(target, DisplayLightFieldGeometry(system))
             .cast<std::shared_ptr<LightField>>();
  }
  CheckGeometryArgument(lf->geometry, "target: geometry");
  CheckArgument([&] { CheckLightFieldValues(*lf, "target"); });
  return lf;
}

// The config step of the solve job (analysis/solve_job.h) for a scene, or a
// compiled system's default solver with its defaults.
SolveConfig ConfigOf(const py::object& display, const std::optional<std::string>& solver, Solution* solution) {
  SolveConfig config;
  if (py::isinstance<Scene>(display)) {
    const Scene& scene = display.cast<const Scene&>();
    py::gil_scoped_release release;
    solution->system = std::make_shared<DisplaySystem>(Compile(scene));
    config = ReadSolveConfig(scene, *solution->system);
  } else {
    if (!py::isinstance<DisplaySystem>(display))
      throw py::type_error("solve: display: expected a layerlab.Scene or layerlab.System, got " + TypeName(display));
    solution->system = display.cast<std::shared_ptr<DisplaySystem>>();
    config.solver = DefaultSolverFor(*solution->system);
    config.options = SolverRegistry::Builtins().get(config.solver).defaults;
  }
  // names the known solvers for an unknown one
  if (solver && *solver != config.solver) UseSolver(*solver, &config);
  return config;
}

py::object Solve(const py::object& display, const py::object& target, std::optional<std::string> solver,
                 std::optional<std::string> sampling, const py::object& callback, const py::kwargs& options) {
  auto solution = std::make_shared<Solution>();
  SolveJob job;
  job.config = ConfigOf(display, solver, solution.get());
  SolveConfig& config = job.config;
  job.system = solution->system.get();
  if (const std::string why = UnsuitableSolver(config.solver, *solution->system); !why.empty())
    RaiseArgumentError(config.solver + " " + why);
  if (sampling) CheckArgument([&] { config.sampling = SamplingFromString(*sampling); });
  for (const auto& [key, value] : options) SetOption(config.options, key.cast<std::string>(), value);
  if (std::string why; !config.options.IsValid(&why)) RaiseArgumentError(why);

  std::unique_ptr<Target> loaded;  // kept through the solve: a traced retinal target reads its scene
  if (!target.is_none()) {
    solution->target = TargetOf(target, *solution->system);
  } else if (!config.target.empty() || !config.target_scene.empty()) {
    py::gil_scoped_release release;
    loaded = LoadOrRenderTarget(config, "target");
    solution->target = std::make_shared<LightField>(std::move(loaded->light_field));
    AttachRetinalTarget(*loaded, &config.options);
  } else {
    throw py::value_error("solve: no target: pass one, or give the scene a \"solve\" section with a target");
  }
  solution->solver = config.solver;
  solution->sampling = config.sampling;

  SolveHooks hooks;
  hooks.Install(config.options, callback, TraceRow);
  std::optional<py::error_already_set>& raised = hooks.raised;
  {
    py::gil_scoped_release release;
    SolvedJob solved = RunSolveJob(job, *solution->target, nullptr);
    solution->model = std::move(solved.model);
    solution->patterns = std::move(solved.patterns);
    solution->report = std::move(solved.report);
  }
  if (raised) {
    if (raised->matches(PyExc_KeyboardInterrupt) && solution->report.IsSolutionUsable()) {
      py::object interrupted = py::module_::import("layerlab.errors").attr("Interrupted");
      py::object value = interrupted("solve interrupted: " + solution->report.message, py::cast(solution));
      PyErr_SetObject(interrupted.ptr(), value.ptr());
      throw py::error_already_set();
    }
    throw std::move(*raised);
  }
  if (!solution->report.IsSolutionUsable()) throw Error("the solve failed: " + solution->report.message);
  return py::cast(solution);
}

// Each pattern in the eye's orientation (AsTheEyeSeesIt), a new (rows, cols, 3) float32 array each.
py::list PatternsAsSeen(const DisplaySystem& system, const Patterns& patterns) {
  py::list list;
  for (size_t k = 0; k < patterns.size(); ++k) {
    const LayerPattern& p = patterns[k];
    list.append(OwningArray(AsTheEyeSeesIt(system.layers[k], p), {p.rows, p.cols, 3}));
  }
  return list;
}

// Patterns from arrays, one (rows, cols, 3) per layer, in [0, 1] as ReadPatterns holds a pattern file to.
Patterns PatternsOf(const DisplaySystem& system, const py::sequence& arrays) {
  return PatternArrays(system, arrays, "synthesize", "", [](const LayerPattern& p, const std::string& name) {
    CheckArgument([&] { CheckTransmittance(p, name); });
  });
}

// The light the display shows with `patterns`: through its LED arrays' spread (systems/source_spread.h).
LightField SeenLight(const DisplayModel& model, const Patterns& patterns) {
  return Synthesize(model, DiffractedPatterns(SeenKernels(model.system(), false), patterns));
}

std::shared_ptr<LightField> Synthesize(const std::shared_ptr<DisplaySystem>& system, const py::sequence& arrays,
                                       std::optional<LightFieldGeometry> geometry, const std::string& sampling) {
  const Patterns patterns = PatternsOf(*system, arrays);
  const ModelRays rays = ModelRaysArg(*system, geometry, sampling, "synthesize");
  py::gil_scoped_release release;
  const DisplayModel model(*system, rays.geometry, rays.sampling);
  return std::make_shared<LightField>(SeenLight(model, patterns));
}

// What the eye sees of the solution, focused at each of `accommodation` (D):
// (states, rows, cols, 3), display-relative linear RGB (retina/retina.h);
// with `natural`, also what it sees of the target light field itself, read as
// the layers are (retina/lightfield_radiance.h), as `layerlab retina --target`.
py::object Retina(const Solution& s, const std::vector<double>& accommodation, double resolution_deg,
                  std::optional<std::pair<double, double>> field_deg, bool natural) {
  // The checks `layerlab retina` makes: its states (ParseOptionValue's, as
  // CheckAccommodationStates), its field and sample size (CheckRetinaSampling).
  const DisplaySystem& system = *s.system;
  const double field_x = field_deg ? field_deg->first : system.fov_x_rad / kRadiansPerDegree;
  const double field_y = field_deg ? field_deg->second : system.fov_y_rad / kRadiansPerDegree;
  CheckArgument([&] {
    CheckAccommodationStates(accommodation, "retina: accommodation");
    CheckRetinaSampling(field_x, field_y, resolution_deg, "retina: field_deg", "retina: resolution_deg");
  });
  const RetinaGrid grid = CenteredOnGaze(
      field_deg
          ? MakeRetinaGrid(field_x * kRadiansPerDegree, field_y * kRadiansPerDegree, resolution_deg * kRadiansPerDegree)
          : MakeRetinaGrid(system.fov_x_rad, system.fov_y_rad, resolution_deg * kRadiansPerDegree),
      system.eye.pose);
  const std::vector<py::ssize_t> shape = {static_cast<py::ssize_t>(accommodation.size()),
                                          static_cast<py::ssize_t>(grid.rows), static_cast<py::ssize_t>(grid.cols), 3};
  py::array_t<float> images(shape), seen(natural ? shape : std::vector<py::ssize_t>{0});
  float* out = images.mutable_data();
  float* out_natural = seen.mutable_data();
  const std::vector<PupilPoint> pupil = PupilSamples(system.eye);
  {
    py::gil_scoped_release release;
    const SceneRadiance scene = natural ? LightFieldRadiance(*s.target, s.sampling) : SceneRadiance{};
    RetinaWorkspace workspace;  // shared by the states, as a focal stack's are
    const EyeOptics optics(system.eye, pupil, grid);
    // What the panels show over a frame (their response), each instant through the panels' diffraction.
    const std::vector<ShownInstant> seen_over_time = SeenOverTime(system, s.patterns);
    for (size_t k = 0; k < accommodation.size(); ++k) {
      const std::array<double, 3> focus = ChannelAccommodation(system.eye, accommodation[k]);
      const Image image = optics.See([&](const RetinaGrid& traced, const std::vector<PupilPoint>& group) {
        return RetinaOfDisplay(*s.model, seen_over_time, DisplayRetinaTables(*s.model, traced, group, focus),
                               &workspace);
      });
      std::copy(image.pixels.begin(), image.pixels.end(), out + k * image.pixels.size());
      if (natural) {
        const Image target = optics.See([&](const RetinaGrid& traced, const std::vector<PupilPoint>& group) {
          return RetinaOfScene(scene, traced, group, focus);
        });
        std::copy(target.pixels.begin(), target.pixels.end(), out_natural + k * target.pixels.size());
      }
    }
  }
  if (natural) return py::make_tuple(images, seen);
  return images;
}

}  // namespace

void BindSolve(py::module_& m) {
  py::class_<Solution, std::shared_ptr<Solution>>(m, "Solution", "Patterns and the report of a solve")
      .def_readonly("solver", &Solution::solver)
      .def_readonly("system", &Solution::system)
      .def_readonly("target", &Solution::target)
      .def_property_readonly(
          "patterns",
          [](py::object self) {
            const Solution& s = self.cast<const Solution&>();
            py::list list;
            for (const LayerPattern& p : s.patterns) list.append(FloatView({p.rows, p.cols, 3}, p.rgb.data(), self));
            return list;
          },
          "one (rows, cols, 3) float32 array per layer (System.layers order): transmittance in [0, 1], the panel's "
          "own pixel order; views of the solution's buffers")
      .def_property_readonly(
          "patterns_as_seen", [](const Solution& s) { return PatternsAsSeen(*s.system, s.patterns); },
          "the patterns in the eye's orientation (x right, y up as the eye sees each layer: a mirror-reversed layer "
          "turned back, so that neighbouring layers line up), as the run report shows them; copies")
      .def_property_readonly(
          "report", [](const Solution& s) { return ReportDict(s.report); },
          "dict: solver, termination, message, iterations, seconds, final_psnr_db, ..., and "
          "trace: a dict of arrays iteration, seconds, objective, psnr_db (row 0: the initial guess)")
      .def_property_readonly("brief_report", [](const Solution& s) { return s.report.BriefReport(); })
      .def_property_readonly("full_report", [](const Solution& s) { return s.report.FullReport(); })
      .def(
          "synthesize",
          [](const Solution& s) {
            py::gil_scoped_release release;
            return std::make_shared<LightField>(SeenLight(*s.model, s.patterns));
          },
          "The light field the display shows with these patterns (the target's geometry)")
      .def(
          "save",
          [](const Solution& s, const py::object& folder, bool write_lightfield) {
            const std::string path = PathArg(folder);
            py::gil_scoped_release release;
            return WriteSolution(*s.model, s.patterns, s.report, path, {.write_lightfield = write_lightfield});
          },
          py::arg("folder"), py::arg("write_lightfield") = false,
          "Writes what `layerlab solve` writes: patterns, panels, trace.csv, report.txt, report.json")
      .def(
          "retina",
          [](const Solution& s, const py::object& accommodation, const py::object& resolution_deg,
             const py::object& field_deg, const py::object& natural) {
            std::optional<std::pair<double, double>> field;
            if (!field_deg.is_none()) {
              const std::vector<double> xy = RealListArg(field_deg, "retina: field_deg");
              if (xy.size() != 2) RaiseArgumentError("retina: field_deg: give (x, y) in degrees");
              field = std::make_pair(xy[0], xy[1]);
            }
            return Retina(s, RealListArg(accommodation, "retina: accommodation"),
                          RealArg(resolution_deg, "retina: resolution_deg"), field,
                          BoolArg(natural, "retina: natural"));
          },
          py::arg("accommodation"), py::kw_only(), py::arg("resolution_deg") = 0.05, py::arg("field_deg") = py::none(),
          py::arg("natural") = false,
          "Retinal images (states, rows, cols, 3) float32 at each of accommodation (list of float, D); "
          "resolution_deg: float, deg per sample (default 0.05); field_deg: (x, y) float deg, or None for the "
          "display's field of view; natural: bool (default False): True returns (display, natural), the second what "
          "the eye sees of the target light field itself")
      .def("__repr__", [](const Solution& s) { return "<layerlab.Solution " + s.report.BriefReport() + ">"; });

  m.def("solve", &Solve, py::arg("display"), py::arg("target") = py::none(), py::kw_only(),
        py::arg("solver") = py::none(), py::arg("sampling") = py::none(), py::arg("callback") = py::none(), SolveDoc());
  m.def(
      "patterns_as_seen",
      [](const std::shared_ptr<DisplaySystem>& system, const py::sequence& patterns) {
        return PatternsAsSeen(*system, PatternsOf(*system, patterns));
      },
      py::arg("system"), py::arg("patterns"),
      "Patterns (one (rows, cols, 3) array per layer, in [0, 1]) in the eye's orientation, as "
      "Solution.patterns_as_seen gives a solution's: new float32 arrays");
  m.def("synthesize", &Synthesize, py::arg("system"), py::arg("patterns"), py::arg("geometry") = py::none(),
        py::arg("sampling") = "nearest",
        "The light field the display shows with these patterns (default geometry: display_geometry(system))");
  m.def(
      "solvers", [] { return SolverRegistry::Builtins().names(); }, "The solvers' names");
  m.attr("_solve_keywords") = KeywordSignature(OptionKeywords());
}

}  // namespace layerlab::python
