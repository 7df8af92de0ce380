// run(scene, out): the main job of `layerlab run` (analysis/run_pipeline.h),
// the same library call the command makes, returning what it computed as
// arrays and tables beside the files; contrast(scenes, section): the
// accommodation sweep of Fig. 5 (analysis/contrast.h) as arrays.
#include <algorithm>
#include <memory>
#include <optional>
#include <string>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "layerlab/analysis/contrast.h"
#include "layerlab/analysis/contrast_option_table.h"
#include "layerlab/analysis/run_config.h"
#include "layerlab/analysis/run_pipeline.h"
#include "layerlab/python/src/arguments.h"
#include "layerlab/python/src/bindings.h"
#include "layerlab/python/src/json_convert.h"
#include "layerlab/python/src/numpy_view.h"
#include "layerlab/python/src/option_keywords.h"
#include "layerlab/python/src/path_arg.h"
#include "layerlab/python/src/result_dicts.h"
#include "layerlab/solvers/solver_option_table.h"
#include "layerlab/systems/compile.h"

namespace py = pybind11;

namespace layerlab::python {
namespace {

py::array_t<double> Array(const std::vector<double>& v) { return py::array_t<double>(v.size(), v.data()); }

// The retinal states as arrays: diopters, the images stacked (states, rows,
// cols, 3) as Solution.retina gives them (one copy: each state has its own
// buffer), natural (None without natural viewing), the mean luminances and each state's PSNR.
py::dict RetinaDict(std::vector<RetinaStateResult>& states) {
  py::dict d;
  std::vector<double> diopters, display_mean, natural_mean;
  for (const RetinaStateResult& s : states) {
    diopters.push_back(s.diopters);
    display_mean.push_back(s.display_mean_cd_m2);
    natural_mean.push_back(s.natural_mean_cd_m2);
  }
  d["diopters"] = Array(diopters);
  d["display_mean_cd_m2"] = Array(display_mean);
  d["natural_mean_cd_m2"] = Array(natural_mean);
  for (size_t k = 0; !states.empty() && k < states.front().scores.size(); ++k) {  // one array per metric's column
    std::vector<double> score;
    for (const RetinaStateResult& s : states) score.push_back(s.scores[k].second);
    d[py::str(states.front().scores[k].first)] = Array(score);
  }
  d["names"] = [&] {
    py::list names;
    for (const RetinaStateResult& s : states) names.append(s.name);
    return names;
  }();
  auto stack = [&](Image RetinaStateResult::*which) -> py::object {
    if (states.empty() || (states.front().*which).pixels.empty()) return py::none();
    const Image& first = states.front().*which;
    const size_t size = first.pixels.size();  // every state's: one retina grid
    py::array_t<float> a({static_cast<py::ssize_t>(states.size()), static_cast<py::ssize_t>(first.height),
                          static_cast<py::ssize_t>(first.width), py::ssize_t{3}});
    for (size_t k = 0; k < states.size(); ++k) {
      Image& image = states[k].*which;
      std::copy(image.pixels.begin(), image.pixels.end(), a.mutable_data() + k * size);
      image = Image{};  // its memory back: the array holds it now
    }
    return a;
  };
  d["display"] = stack(&RetinaStateResult::display);
  d["natural"] = stack(&RetinaStateResult::natural);
  return d;
}

py::dict RunDict(RunOutcome&& done) {
  auto outcome = std::make_shared<RunOutcome>(std::move(done));
  py::dict d;
  d["written"] = outcome->written;
  d["removed"] = outcome->removed;
  d["recovered"] = outcome->recovered;
  d["warnings"] = outcome->warnings;
  d["solved"] = outcome->solved;
  d["compare_table"] = outcome->compare_table;
  d["index_html"] = outcome->index_html;
  d["report"] = py::none();
  if (outcome->solved) {
    d["psnr_db"] = outcome->report.final_psnr_db;
    d["solver"] = outcome->report.solver;
    d["iterations"] = outcome->report.iterations;
    d["seconds"] = outcome->report.seconds;
    d["report"] = ReportDict(outcome->report);
  }
  // The patterns: views of the outcome's own buffers, which they keep alive (no copy).
  py::capsule owner(new std::shared_ptr<RunOutcome>(outcome),
                    [](void* p) { delete static_cast<std::shared_ptr<RunOutcome>*>(p); });
  py::list patterns;
  for (const LayerPattern& p : outcome->patterns) patterns.append(FloatView({p.rows, p.cols, 3}, p.rgb.data(), owner));
  d["patterns"] = patterns;
  d["retina"] = outcome->retina.empty() ? py::object(py::none()) : py::object(RetinaDict(outcome->retina));
  py::list curves;
  for (const ContrastCurve& c : outcome->contrast) curves.append(CurveDict(c));
  d["contrast"] = curves;
  d["compare"] = outcome->compare.empty()
                     ? py::object(py::none())
                     : py::object(CompareColumns(outcome->compare_scenes, outcome->compare, {}, {}));
  return d;
}

// contrast()'s keywords: the contrast option table's Python names
// (analysis/contrast_option_table.h). A key of the run section's "contrast"
// object goes into `section` and is read by its reader with its checks; the
// others are set here and checked by ContrastOptions::IsValid.
const std::vector<const OptionSpec*>& ContrastKeywords() {
  static const std::vector<const OptionSpec*> entries = KeywordEntries(ContrastOptionTable(), true);
  return entries;
}

const char* ContrastDoc() {
  static const std::string doc =
      "Normalized contrast against accommodation (Fig. 5): one dict per display, depth and frequency, with "
      "\"natural\" for natural viewing. `section` is a run section's \"contrast\" object (default: the first "
      "scene's); a keyword sets one of its options over it (docs/scene-reference.md, run.contrast):\n" +
      KeywordDoc(ContrastKeywords());
  return doc.c_str();
}

// The section with the keywords of its keys put in; the others' entries in *rest.
nlohmann::json ContrastSection(const py::object& section, const py::kwargs& keywords,
                               std::vector<std::pair<const ContrastOptionEntry*, py::handle>>* rest) {
  nlohmann::json given = section.is_none() ? nlohmann::json() : ToJson(section, "contrast()", "/run/contrast");
  for (const auto& [name, value] : keywords) {
    const ContrastOptionEntry& e =
        *FindContrastOption(KeywordEntry(ContrastKeywords(), name.cast<std::string>(), "contrast").key);
    if (!e.in_scene) {
      rest->push_back({&e, value});
      continue;
    }
    if (given.is_null()) given = nlohmann::json::object();
    if (given.contains(e.key)) RaiseArgumentError("contrast: " + e.key + " is both in the section and a keyword");
    try {
      given[e.key] = e.key == "factorized_for" && py::hasattr(value, "__fspath__")
                         ? nlohmann::json(PathArg(value))
                         : ToJson(value, "contrast()", "/run/contrast/" + e.key);
    } catch (const py::type_error& wrong) {  // named by the keyword given, the section's key beside it
      throw py::type_error("contrast: " + name.cast<std::string>() + ": " + wrong.what());
    }
  }
  return given;
}

// The displays of the first scene file and the others; the options are those
// of a run section's "contrast" object (docs/run-section.md), read by the same
// reader with the same checks: `section` and the keywords, or else the first scene's own.
py::list Contrast(const py::object& scenes, const py::object& section, const py::kwargs& keywords) {
  std::vector<std::string> files;
  if (py::isinstance<py::str>(scenes) || py::hasattr(scenes, "__fspath__")) {
    files.push_back(PathArg(scenes));
  } else if (py::isinstance<py::iterable>(scenes)) {
    size_t k = 0;
    for (const py::handle& f : scenes) {
      if (!py::isinstance<py::str>(f) && !py::hasattr(f, "__fspath__"))
        throw py::type_error("contrast: scenes[" + std::to_string(k) + "]: expected a scene file's path, got " +
                             TypeName(f));
      files.push_back(PathArg(f));
      ++k;
    }
  } else {
    throw py::type_error("contrast: scenes: expected a scene file's path or a list of them, got " + TypeName(scenes));
  }
  if (files.empty()) throw py::value_error("contrast: no scene");
  std::vector<std::pair<const ContrastOptionEntry*, py::handle>> rest;
  nlohmann::json given = ContrastSection(section, keywords, &rest);
  ContrastOptions set_here;  // the keywords the scene does not hold, checked before anything is loaded
  for (const auto& [entry, value] : rest) SetKeyword(set_here, *entry, value);
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
      options.document = {{"run", {{"contrast", given}}}};
    }
    ContrastRunConfig config = ReadRunConfig(options, displays.front().system).contrast;
    for (const auto& [entry, value] : rest) entry->set(config.options, entry->get(set_here));
    for (const std::string& f : config.scenes) displays.push_back(LoadContrastDisplay(f));
    std::optional<ContrastDisplay> foreign;
    if (!config.factorized_for.empty()) foreign = LoadContrastDisplay(config.factorized_for);
    curves = RunContrast(displays, config.options, foreign ? &*foreign : nullptr);
  }
  py::list list;
  for (const ContrastCurve& c : curves) list.append(CurveDict(c));
  return list;
}

}  // namespace

void BindAnalysis(py::module_& m) {
  m.def(
      "run",
      [](const py::object& scene, const py::object& out, const py::object& iterations, const py::object& threads) {
        RunRequest request;
        request.scene = PathArg(scene), request.out = PathArg(out), request.keep_images = true;
        // The main solve's, checked as solve() checks them (the solver option table's ranges).
        auto solve_option = [](const py::object& value, const char* key) {
          const SolverOptionEntry& e = *FindSolverOption(key);
          return static_cast<int>(IntegerArg(value, std::string("run: ") + key, static_cast<long long>(e.range.min),
                                             static_cast<long long>(e.range.max), e.Constraint()));
        };
        if (!iterations.is_none()) request.iterations = solve_option(iterations, "iterations");
        if (!threads.is_none()) request.threads = solve_option(threads, "threads");
        RunOutcome outcome;
        {
          py::gil_scoped_release release;
          outcome = RunPipeline(request);
        }
        return RunDict(std::move(outcome));
      },
      py::arg("scene"), py::arg("out"), py::kw_only(), py::arg("iterations") = py::none(),
      py::arg("threads") = py::none(),
      "Runs the scene's \"solve\" and \"run\" sections like `layerlab run SCENE --out OUT`; returns what was written "
      "and what was computed: report, patterns (arrays), retina (arrays), contrast (curves), compare (columns)");
  m.def("contrast", &Contrast, py::arg("scenes"), py::arg("section") = py::none(), ContrastDoc());
  m.attr("_contrast_keywords") = KeywordSignature(ContrastKeywords());
}

}  // namespace layerlab::python
