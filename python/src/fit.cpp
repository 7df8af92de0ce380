// fit(scene, measurements, ...): `layerlab fit` (calibration/, Ceres) returning
// the fitted parameters as columns with their standard deviations, the report,
// and the calibrated scene as a dict, as the command would write it into the
// working directory (relative paths rebased to it, as dict scenes are read).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <optional>
#include <string>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "layerlab/calibration/calibrated_scene.h"
#include "layerlab/calibration/calibration.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/units.h"
#include "layerlab/python/src/bindings.h"
#include "layerlab/python/src/json_convert.h"
#include "layerlab/python/src/path_arg.h"
#include "layerlab/systems/compile.h"

namespace py = pybind11;

namespace layerlab::python {
namespace {

bool IsPath(const py::handle& value) { return py::isinstance<py::str>(value) || py::hasattr(value, "__fspath__"); }

// The columns of the fitted parameters, each value in its `unit`: m, D, deg (the API's one angle unit), or "".
py::dict ParameterTable(const std::vector<ParameterEstimate>& parameters) {
  const auto n = static_cast<py::ssize_t>(parameters.size());
  py::list element, quantity, status, unit;
  py::array_t<double> scene_value(n), value(n), std_dev(n);
  py::array_t<bool> derived(n);
  for (py::ssize_t i = 0; i < n; ++i) {
    const ParameterEstimate& p = parameters[i];
    const std::string si = ParameterSiUnit(p.quantity);
    const double scale = si == "rad" ? 1 / kRadiansPerDegree : 1;
    element.append(p.element), quantity.append(p.quantity), status.append(ToString(p.status));
    unit.append(si == "rad" ? "deg" : si);
    scene_value.mutable_at(i) = p.scene_value * scale, value.mutable_at(i) = p.value * scale;
    std_dev.mutable_at(i) = p.std_dev.value_or(NAN) * scale, derived.mutable_at(i) = p.derived;
  }
  py::dict d;
  d["element"] = element, d["quantity"] = quantity, d["unit"] = unit, d["scene_value"] = scene_value;
  d["value"] = value, d["std_dev"] = std_dev, d["status"] = status, d["derived"] = derived;
  return d;
}

// The report as the API gives angles, in degrees: a parameter row of unit "rad" in "deg", and a key ending
// "_rad" or "_arcmin" renamed "_deg" with its value converted (report.json itself stays SI).
void AnglesInDegrees(nlohmann::json* j) {
  if (j->is_array()) {
    for (nlohmann::json& item : *j) AnglesInDegrees(&item);
    return;
  }
  if (!j->is_object()) return;
  if (j->contains("unit") && (*j)["unit"] == "rad") {
    for (const char* key : {"value", "scene_value", "std_dev"})
      if (j->contains(key) && (*j)[key].is_number()) (*j)[key] = (*j)[key].get<double>() / kRadiansPerDegree;
    (*j)["unit"] = "deg";
  }
  nlohmann::json renamed = nlohmann::json::object();
  for (auto& [key, value] : j->items()) {
    AnglesInDegrees(&value);
    const auto ends = [&](const std::string& suffix) {
      return key.size() > suffix.size() && key.compare(key.size() - suffix.size(), suffix.size(), suffix) == 0;
    };
    const double scale = ends("_rad") ? 1 / kRadiansPerDegree : ends("_arcmin") ? 1.0 / 60 : 0;
    if (scale == 0) {
      renamed[key] = value;
      continue;
    }
    const std::string name = key.substr(0, key.rfind('_')) + "_deg";
    if (value.is_number()) {
      renamed[name] = value.get<double>() * scale;
    } else if (value.is_array() &&
               std::all_of(value.begin(), value.end(), [](const auto& v) { return v.is_number(); })) {
      nlohmann::json a = nlohmann::json::array();
      for (const auto& v : value) a.push_back(v.get<double>() * scale);
      renamed[name] = a;
    } else {
      renamed[key] = value;
    }
  }
  *j = std::move(renamed);
}

py::dict Fit(const py::object& scene, const py::object& measurements, const std::string& loss,
             const std::string& reference, const std::string& focal_length, const std::string& lens_gaps,
             const std::string& distortion, bool accept_model_error, std::optional<double> marker_loss_deg,
             std::optional<double> luminance_loss_scale) {
  CalibrationOptions options;
  try {
    options.loss = RobustLossFromString(loss);
    options.reference = AxisReferenceFromString(reference);
  } catch (const Error& e) {
    throw py::value_error(std::string(loss == ToString(options.loss) ? "fit: reference: " : "fit: loss: ") +
                          e.message());
  }
  try {
    options.focal_length = FitChoiceFromString(focal_length);
    options.lens_gaps = FitChoiceFromString(lens_gaps);
    options.distortion = FitChoiceFromString(distortion);
  } catch (const Error& e) {
    throw py::value_error("fit: focal_length / lens_gaps / distortion: " + e.message());
  }
  options.accept_model_error = accept_model_error;
  if (marker_loss_deg) options.marker_loss_scale_rad = *marker_loss_deg * kRadiansPerDegree;
  if (luminance_loss_scale) options.luminance_loss_scale = *luminance_loss_scale;
  if (std::string why; !options.IsValid(&why)) throw py::value_error("fit: " + why);

  // The scene in file order (the calibrated one keeps it) and where relative paths start from.
  const bool scene_is_path = IsPath(scene);
  const std::string scene_file = scene_is_path ? PathArg(scene) : "<dict>";
  std::optional<nlohmann::ordered_json> scene_document;
  if (!scene_is_path) {
    if (!py::isinstance<py::dict>(scene)) throw py::type_error("fit: the scene is a path or a dict");
    scene_document = nlohmann::ordered_json::parse(JsonText(scene, "<dict>"));
  }
  std::optional<nlohmann::json> measurements_document;
  const bool measurements_are_path = IsPath(measurements);
  if (!measurements_are_path) {
    if (!py::isinstance<py::dict>(measurements)) throw py::type_error("fit: the measurements are a path or a dict");
    measurements_document = ToJson(measurements, "<dict>");
  }
  const std::string measurements_file = measurements_are_path ? PathArg(measurements) : "<dict>";

  CalibrationReport report;
  nlohmann::ordered_json calibrated;
  {
    py::gil_scoped_release release;
    const DisplaySystem system = Compile(scene_is_path ? LoadScene(scene_file)
                                                       : ParseScene(nlohmann::json::parse(scene_document->dump()),
                                                                    scene_file, ElementRegistry::WithBuiltins()));
    const Measurements m = measurements_are_path ? ReadMeasurementsFile(measurements_file)
                                                 : ParseMeasurements(*measurements_document, measurements_file);
    CheckMeasurements(m, system);  // a panel or pixel that is not the scene's, with its place
    CalibratedDisplay display;
    report = Calibrate(system, m, options, &display);
    if (!report.IsSolutionUsable()) throw Error("the calibration failed: " + report.message);
    calibrated =
        CalibratedSceneDocument(scene_is_path ? ReadDocumentInOrder(scene_file) : *scene_document, scene_file, display);
    if (scene_is_path)
      RebaseRelativePaths(calibrated, std::filesystem::absolute(scene_file).string(),
                          (std::filesystem::current_path() / "calibrated.json").string());
    try {
      Compile(ParseScene(nlohmann::json::parse(calibrated.dump()), "<calibrated>", ElementRegistry::WithBuiltins()));
    } catch (const Error& e) {
      throw Error("fit: the calibrated scene does not compile (" + e.message() + ")");
    }
  }
  py::dict d;
  d["parameters"] = ParameterTable(report.parameters);
  d["scene"] = py::module_::import("json").attr("loads")(calibrated.dump());  // key order kept
  nlohmann::json report_json = report.ToJson();
  AnglesInDegrees(&report_json);
  d["report"] = FromJson(report_json);
  d["brief"] = report.BriefReport();
  d["full"] = report.FullReport();
  d["warnings"] = report.warnings;
  return d;
}

}  // namespace

void BindFit(py::module_& m) {
  m.def("fit", &Fit, py::arg("scene"), py::arg("measurements"), py::kw_only(), py::arg("loss") = "none",
        py::arg("reference") = "camera", py::arg("focal_length") = "auto", py::arg("lens_gaps") = "auto",
        py::arg("distortion") = "hold", py::arg("accept_model_error") = false, py::arg("marker_loss_deg") = py::none(),
        py::arg("luminance_loss_scale") = py::none(),
        "Calibrates a scene from measurements of the built display, as `layerlab fit` (Ceres): a dict with "
        "parameters (columns element, quantity, unit, scene_value, value, std_dev, status, derived; angles in deg), "
        "scene (the calibrated scene, paths relative to the working directory), report (report.json's content with "
        "angles in deg: keys ending _deg), brief, full, warnings. marker_loss_deg: float or None, the markers' "
        "robust loss scale (deg); luminance_loss_scale: float or None");
}

}  // namespace layerlab::python
