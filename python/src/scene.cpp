// load_scene(path_or_dict) and compile(scene): the scene and its compiled
// display system as Python objects (read-only; they refer into the C++ system,
// which they keep alive).
#include <filesystem>
#include <memory>
#include <string>

#include <pybind11/stl.h>

#include "layerlab/python/src/bindings.h"
#include "layerlab/python/src/json_convert.h"
#include "layerlab/python/src/path_arg.h"
#include "layerlab/systems/compile.h"
#include "layerlab/systems/scene.h"

namespace py = pybind11;

namespace layerlab::python {
namespace {

std::shared_ptr<Scene> LoadSceneFrom(const py::object& source, const std::string& file) {
  if (py::isinstance<py::dict>(source)) {
    nlohmann::json document = ToJson(source, file.empty() ? "<dict>" : file);
    py::gil_scoped_release release;
    return std::make_shared<Scene>(
        ParseScene(std::move(document), file.empty() ? "<dict>" : file, ElementRegistry::WithBuiltins()));
  }
  if (!py::isinstance<py::str>(source) && !py::hasattr(source, "__fspath__"))
    throw py::type_error("load_scene: expected a path (str or os.PathLike) or a dict, got " +
                         py::str(py::type::of(source).attr("__name__")).cast<std::string>());
  const std::string path = PathArg(source);
  py::gil_scoped_release release;
  return std::make_shared<Scene>(LoadScene(path));
}

std::shared_ptr<DisplaySystem> CompileScene(const Scene& scene) {
  py::gil_scoped_release release;
  return std::make_shared<DisplaySystem>(Compile(scene));
}

// A list of the elements of `items`, each referring into `owner`.
template <typename T>
py::list ListOf(const std::vector<T>& items, py::handle owner) {
  py::list list;
  for (const T& item : items) list.append(py::cast(&item, py::return_value_policy::reference_internal, owner));
  return list;
}

// A property: one field of every layer (or branch), as a list.
template <typename Item, typename Field>
auto Each(std::vector<Item> DisplaySystem::*items, Field Item::*field) {
  return [items, field](const DisplaySystem& s) {
    std::vector<Field> values;
    for (const Item& item : s.*items) values.push_back(item.*field);
    return values;
  };
}

void BindSceneClass(py::module_& m) {
  py::class_<Scene, std::shared_ptr<Scene>>(m, "Scene", "A parsed scene file (layerlab-scene/1)")
      .def_readonly("file", &Scene::file)
      .def_readonly("name", &Scene::name)
      .def_readonly("description", &Scene::description)
      .def_readonly("subframes", &Scene::subframes)
      .def_readonly("frame_rate", &Scene::frame_rate_hz, "Hz")
      .def_property_readonly(
          "document", [](const Scene& s) { return FromJson(s.document); }, "The whole scene as a dict (a copy)")
      .def_property_readonly("elements",
                             [](const Scene& s) {
                               py::list names;
                               for (const SceneNode& node : s.nodes) names.append(node.element->name());
                               return names;
                             })
      .def("compile", &CompileScene, "The optically equivalent display system (layers, branches)")
      .def("__repr__", [](const Scene& s) { return "<layerlab.Scene " + s.file + ": " + s.name + ">"; });
}

void BindLayer(py::module_& m) {
  py::class_<PathStep>(m, "PathStep", "One element between the eye and a panel")
      .def_readonly("element", &PathStep::element)
      .def_readonly("type", &PathStep::type)
      .def_readonly("port", &PathStep::port)
      .def_readonly("position", &PathStep::position_m, "m of unfolded path from the pupil, or None")
      .def_readonly("power", &PathStep::power_diopters, "1/m")
      .def_readonly("flips_x", &PathStep::flips_x)
      .def_readonly("flips_y", &PathStep::flips_y);

  py::class_<VirtualLayer>(m, "Layer", "A virtual layer in eye space (meters, radians)")
      .def_readonly("name", &VirtualLayer::name)
      .def_readonly("element", &VirtualLayer::element)
      .def_readonly("subframe", &VirtualLayer::subframe)
      .def_readonly("branch", &VirtualLayer::branch)
      .def_readonly("position_in_branch", &VirtualLayer::position_in_branch)
      .def_readonly("diopters", &VirtualLayer::diopters)
      .def_readonly("depth", &VirtualLayer::depth_m, "m (inf at 0 D)")
      .def_readonly("panel_distance", &VirtualLayer::panel_distance_m, "m")
      .def_readonly("position", &VirtualLayer::position_m, "m")
      .def_readonly("magnification", &VirtualLayer::magnification)
      .def_readonly("inverted", &VirtualLayer::inverted)
      .def_readonly("pitch_x", &VirtualLayer::pitch_x_m, "m")
      .def_readonly("pitch_y", &VirtualLayer::pitch_y_m, "m")
      .def_readonly("tan_pitch_x", &VirtualLayer::tan_pitch_x)
      .def_readonly("tan_pitch_y", &VirtualLayer::tan_pitch_y)
      .def_readonly("cols", &VirtualLayer::cols)
      .def_readonly("rows", &VirtualLayer::rows)
      .def_readonly("offset_x", &VirtualLayer::eye_from_layer_tan_x)
      .def_readonly("offset_y", &VirtualLayer::eye_from_layer_tan_y)
      .def_readonly("rotation", &VirtualLayer::rotation_rad, "rad")
      .def_readonly("flip_x", &VirtualLayer::flip_x)
      .def_readonly("flip_y", &VirtualLayer::flip_y)
      .def_readonly("fov_x", &VirtualLayer::fov_x_rad, "rad")
      .def_readonly("fov_y", &VirtualLayer::fov_y_rad, "rad")
      .def_readonly("max_cpd", &VirtualLayer::max_cpd)
      .def_property_readonly("path",
                             [](py::object self) { return ListOf(self.cast<const VirtualLayer&>().path, self); })
      .def("__repr__", [](const VirtualLayer& l) {
        return "<layerlab.Layer " + l.name + " at " + std::to_string(l.diopters) + " D, M " +
               std::to_string(l.magnification) + ">";
      });
}

void BindSystem(py::module_& m) {
  py::class_<Branch>(m, "Branch", "Layers that multiply; branches add")
      .def_readonly("name", &Branch::name)
      .def_readonly("subframe", &Branch::subframe)
      .def_readonly("layers", &Branch::layers, "indices into System.layers, nearest the eye first")
      .def_readonly("optics_efficiency", &Branch::optics_efficiency, "per channel (R, G, B)")
      .def_readonly("efficiency", &Branch::efficiency, "per channel, times the panels' maximum transmittance")
      .def_readonly("backlight", &Branch::backlight)
      .def_readonly("backlight_luminance", &Branch::backlight_luminance_cd_m2, "cd/m^2");

  py::class_<DisplaySystem, std::shared_ptr<DisplaySystem>>(m, "System", "A compiled display system")
      .def_readonly("name", &DisplaySystem::name)
      .def_readonly("file", &DisplaySystem::file)
      .def_readonly("lens", &DisplaySystem::lens)
      .def_readonly("focal_length", &DisplaySystem::focal_length_m, "m")
      .def_readonly("subframes", &DisplaySystem::subframes)
      .def_readonly("frame_rate", &DisplaySystem::frame_rate_hz, "Hz")
      .def_readonly("fov_x", &DisplaySystem::fov_x_rad, "rad")
      .def_readonly("fov_y", &DisplaySystem::fov_y_rad, "rad")
      .def_readonly("max_cpd", &DisplaySystem::max_cpd)
      .def_readonly("peak_luminance", &DisplaySystem::peak_luminance_cd_m2, "cd/m^2 per channel")
      .def_readonly("brightness_efficiency", &DisplaySystem::brightness_efficiency, "per channel")
      .def_readonly("luminance_efficiency", &DisplaySystem::luminance_efficiency)
      .def_readonly("components", &DisplaySystem::components)
      .def_readonly("warnings", &DisplaySystem::warnings)
      .def_property_readonly(
          "layers", [](py::object self) { return ListOf(self.cast<const DisplaySystem&>().layers, self); },
          "farthest first")
      .def_property_readonly("branches",
                             [](py::object self) { return ListOf(self.cast<const DisplaySystem&>().branches, self); })
      .def_property_readonly("depths", Each(&DisplaySystem::layers, &VirtualLayer::depth_m), "m, one per layer")
      .def_property_readonly("diopters", Each(&DisplaySystem::layers, &VirtualLayer::diopters))
      .def_property_readonly("magnifications", Each(&DisplaySystem::layers, &VirtualLayer::magnification))
      .def_property_readonly("efficiencies", Each(&DisplaySystem::branches, &Branch::efficiency),
                             "per branch, (R, G, B)")
      .def("__repr__", [](const DisplaySystem& s) {
        return "<layerlab.System " + s.name + ": " + std::to_string(s.layers.size()) + " layers, " +
               std::to_string(s.branches.size()) + " branches>";
      });
}

// After the classes, so that their signatures name layerlab.Scene and layerlab.System, not the C++ types.
void BindSceneFunctions(py::module_& m) {
  m.def("load_scene", &LoadSceneFrom, py::arg("source"), py::arg("file") = "",
        "A scene from a file path or a dict (then `file` names it in errors, default \"<dict>\")");
  m.def("compile", &CompileScene, py::arg("scene"), "The display system of a scene");
}

}  // namespace

void BindScene(py::module_& m) {
  BindLayer(m);
  BindSystem(m);
  BindSceneClass(m);  // after System: Scene.compile returns one
  BindSceneFunctions(m);
}

}  // namespace layerlab::python
