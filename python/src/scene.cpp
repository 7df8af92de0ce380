// load_scene(path_or_dict) and compile(scene): the scene and its compiled
// display system as Python objects (read-only; they refer into the C++ system,
// which they keep alive).
#include <filesystem>
#include <memory>
#include <string>

#include <pybind11/stl.h>

#include "layerlab/framework/units.h"
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
      .def_readonly("file", &Scene::file, "the scene file's path, or the name a dict scene was given")
      .def_readonly("name", &Scene::name, "the scene's name")
      .def_readonly("description", &Scene::description, "the scene's description")
      .def_readonly("subframes", &Scene::subframes, "patterns shown per frame (1: not time-multiplexed)")
      .def_readonly("frame_rate_hz", &Scene::frame_rate_hz, "frames per second (Hz)")
      .def_property_readonly(
          "document", [](const Scene& s) { return FromJson(s.document); }, "The whole scene as a dict (a copy)")
      .def_property_readonly(
          "elements",
          [](const Scene& s) {
            py::list names;
            for (const SceneNode& node : s.nodes) names.append(node.element->name());
            return names;
          },
          "the elements' names, in file order")
      .def("compile", &CompileScene, "The optically equivalent display system (layers, branches)")
      .def("__repr__", [](const Scene& s) { return "<layerlab.Scene " + s.file + ": " + s.name + ">"; });
}

void BindLayer(py::module_& m) {
  py::class_<PathStep>(m, "PathStep", "One element between the eye and a panel")
      .def_readonly("element", &PathStep::element, "the element's name")
      .def_readonly("type", &PathStep::type, "the element's type (thin_lens, half_mirror, ...)")
      .def_readonly("port", &PathStep::port, "the combiner port this path takes (empty for other elements)")
      .def_readonly("position_m", &PathStep::position_m, "m of unfolded path from the pupil, or None")
      .def_readonly("power_diopters", &PathStep::power_diopters, "optical power (D = 1/m)")
      .def_readonly("flips_x", &PathStep::flips_x, "whether it mirrors x (a fold mirror, a reflected port)")
      .def_readonly("flips_y", &PathStep::flips_y, "whether it mirrors y");

  py::class_<VirtualLayer>(m, "Layer",
                           "A virtual layer in eye space: lengths in m (names ending _m), angles in degrees (_deg)")
      .def_readonly("name", &VirtualLayer::name, "the panel element, and \"@k\" (1-based) for subframe k")
      .def_readonly("element", &VirtualLayer::element, "the panel element's name")
      .def_readonly("subframe", &VirtualLayer::subframe, "0-based subframe")
      .def_readonly("branch", &VirtualLayer::branch, "index into System.branches")
      .def_readonly("position_in_branch", &VirtualLayer::position_in_branch, "0 is nearest the eye")
      .def_readonly("diopters", &VirtualLayer::diopters, "the virtual image's vergence seen from the eye (D = 1/m)")
      .def_readonly("depth_m", &VirtualLayer::depth_m, "distance from the pupil (m; inf at 0 D)")
      .def_readonly("panel_distance_m", &VirtualLayer::panel_distance_m,
                    "the panel's unfolded distance from the pupil (m)")
      .def_readonly("position_m", &VirtualLayer::position_m, "the panel's position along the unfolded path (m)")
      .def_readonly("magnification", &VirtualLayer::magnification,
                    "M, signed: negative when a real intermediate image inverts it")
      .def_readonly("inverted", &VirtualLayer::inverted, "M < 0: the image is turned by 180 degrees")
      .def_readonly("pitch_x_m", &VirtualLayer::pitch_x_m, "the virtual pixel pitch (m)")
      .def_readonly("pitch_y_m", &VirtualLayer::pitch_y_m, "the virtual pixel pitch (m)")
      .def_readonly("tan_pitch_x", &VirtualLayer::tan_pitch_x,
                    "tangent of the angle per pixel, seen from the pupil center")
      .def_readonly("tan_pitch_y", &VirtualLayer::tan_pitch_y,
                    "tangent of the angle per pixel, seen from the pupil center")
      .def_readonly("cols", &VirtualLayer::cols, "pixels across (the active region)")
      .def_readonly("rows", &VirtualLayer::rows, "pixels down (the active region)")
      .def_readonly("offset_tan_x", &VirtualLayer::eye_from_layer_tan_x,
                    "the grid center's direction from the pupil, as a tangent")
      .def_readonly("offset_tan_y", &VirtualLayer::eye_from_layer_tan_y,
                    "the grid center's direction from the pupil, as a tangent")
      .def_property_readonly(
          "rotation_deg", [](const VirtualLayer& l) { return l.rotation_rad / kRadiansPerDegree; },
          "the grid's rotation about the axis (deg)")
      .def_readonly("flip_x", &VirtualLayer::flip_x, "whether the eye sees the panel's x mirrored")
      .def_readonly("flip_y", &VirtualLayer::flip_y, "whether the eye sees the panel's y mirrored")
      .def_property_readonly(
          "fov_x_deg", [](const VirtualLayer& l) { return l.fov_x_rad / kRadiansPerDegree; },
          "field of view across (deg)")
      .def_property_readonly(
          "fov_y_deg", [](const VirtualLayer& l) { return l.fov_y_rad / kRadiansPerDegree; },
          "field of view down (deg)")
      .def_readonly("max_cpd", &VirtualLayer::max_cpd, "Nyquist frequency at the grid center (cycles per degree)")
      .def_property_readonly(
          "path", [](py::object self) { return ListOf(self.cast<const VirtualLayer&>().path, self); },
          "[PathStep]: the elements between the eye and the panel, eye first")
      .def("__repr__", [](const VirtualLayer& l) {
        return "<layerlab.Layer " + l.name + " at " + std::to_string(l.diopters) + " D, M " +
               std::to_string(l.magnification) + ">";
      });
}

void BindSystem(py::module_& m) {
  py::class_<Branch>(m, "Branch", "Layers that multiply; branches add")
      .def_readonly("name", &Branch::name, "\"bs.reflected\", or \"main\" without a combiner; \"@k\" for subframe k")
      .def_readonly("subframe", &Branch::subframe, "0-based subframe")
      .def_readonly("layers", &Branch::layers, "indices into System.layers, nearest the eye first")
      .def_readonly("optics_efficiency", &Branch::optics_efficiency, "per channel (R, G, B)")
      .def_readonly("efficiency", &Branch::efficiency, "per channel, times the panels' maximum transmittance")
      .def_readonly("backlight", &Branch::backlight, "the backlight element's name")
      .def_readonly("backlight_luminance_cd_m2", &Branch::backlight_luminance_cd_m2,
                    "the backlight's luminance (cd/m^2)");

  py::class_<DisplaySystem, std::shared_ptr<DisplaySystem>>(m, "System", "A compiled display system")
      .def_readonly("name", &DisplaySystem::name, "the scene's name")
      .def_readonly("file", &DisplaySystem::file, "the scene file it was compiled from")
      .def_readonly("lens", &DisplaySystem::lens,
                    "the magnifier when every path holds one and the same lens (else empty)")
      .def_readonly("focal_length_m", &DisplaySystem::focal_length_m, "that lens's focal length (m)")
      .def_readonly("subframes", &DisplaySystem::subframes, "patterns shown per frame (1: not time-multiplexed)")
      .def_readonly("frame_rate_hz", &DisplaySystem::frame_rate_hz, "frames per second (Hz)")
      .def_property_readonly(
          "fov_x_deg", [](const DisplaySystem& s) { return s.fov_x_rad / kRadiansPerDegree; },
          "field of view across (deg)")
      .def_property_readonly(
          "fov_y_deg", [](const DisplaySystem& s) { return s.fov_y_rad / kRadiansPerDegree; },
          "field of view down (deg)")
      .def_readonly("max_cpd", &DisplaySystem::max_cpd, "the finest layer's Nyquist frequency (cycles per degree)")
      .def_readonly("peak_luminance_cd_m2", &DisplaySystem::peak_luminance_cd_m2,
                    "the display's full white per channel (cd/m^2)")
      .def_readonly("brightness_efficiency", &DisplaySystem::brightness_efficiency,
                    "full white over the backlight, per channel (a fraction)")
      .def_readonly("luminance_efficiency", &DisplaySystem::luminance_efficiency,
                    "the same, Rec. 709 luminance-weighted (a fraction)")
      .def_readonly("components", &DisplaySystem::components, "what this system uses, in words")
      .def_readonly("warnings", &DisplaySystem::warnings, "the compiler's warnings")
      .def_property_readonly(
          "layers", [](py::object self) { return ListOf(self.cast<const DisplaySystem&>().layers, self); },
          "farthest first")
      .def_property_readonly(
          "branches", [](py::object self) { return ListOf(self.cast<const DisplaySystem&>().branches, self); },
          "[Branch]: layers that multiply; branches add")
      .def_property_readonly("depths_m", Each(&DisplaySystem::layers, &VirtualLayer::depth_m),
                             "each layer's depth_m (m)")
      .def_property_readonly("diopters", Each(&DisplaySystem::layers, &VirtualLayer::diopters),
                             "each layer's diopters (D)")
      .def_property_readonly("magnifications", Each(&DisplaySystem::layers, &VirtualLayer::magnification),
                             "each layer's magnification")
      .def_property_readonly("efficiencies", Each(&DisplaySystem::branches, &Branch::efficiency),
                             "each branch's efficiency, (R, G, B)")
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
