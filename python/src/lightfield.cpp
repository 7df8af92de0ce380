// Light fields: the geometry, a light field whose .rgb is a NumPy view of its
// own buffer (views, rows, cols, 3), reading and writing the folder format
// (docs/lightfield-format.md), rendering a target scene, wrapping an array.
#include <cstring>
#include <memory>
#include <string>

#include <pybind11/stl.h>

#include "layerlab/framework/lightfield_io.h"
#include "layerlab/python/src/arguments.h"
#include "layerlab/python/src/bindings.h"
#include "layerlab/python/src/numpy_view.h"
#include "layerlab/python/src/path_arg.h"
#include "layerlab/systems/display_model.h"
#if LAYERLAB_WITH_EMBREE
#include "layerlab/targets/target_renderer.h"
#include "layerlab/targets/target_scene.h"
#endif

namespace py = pybind11;

namespace layerlab::python {
namespace {

std::vector<py::ssize_t> RgbShape(const LightFieldGeometry& g) {
  return {static_cast<py::ssize_t>(g.view_count()), g.rows, g.cols, 3};
}
const char* kRgbAxes = "(views, rows, cols, RGB; views = views_y * views_x, row-major)";

// The one copy of wrapping an array: a LightField owns its buffer (huge pages, framework/lightfield.h).
std::shared_ptr<LightField> FromArray(const py::handle& array, const LightFieldGeometry& geometry) {
  CheckGeometryArgument(geometry, "LightField: geometry");
  auto a = FloatArrayOfShape(array, RgbShape(geometry), "LightField", kRgbAxes);
  auto lf = std::make_shared<LightField>(geometry);
  std::memcpy(lf->rgb.data(), a.data(), lf->rgb.size() * sizeof(float));
  return lf;
}

// Each number's type here, the limits by the check a light-field manifest goes through.
LightFieldGeometry GeometryArguments(const py::handle& origin_z, const py::handle& window_left,
                                     const py::handle& window_top, const py::handle& window_width,
                                     const py::handle& window_height, const py::handle& cols, const py::handle& rows,
                                     const py::handle& views_x, const py::handle& views_y,
                                     const py::handle& eyebox_width, const py::handle& eyebox_height) {
  const std::string what = "LightFieldGeometry: ";
  auto real = [&](const py::handle& v, const char* name) { return RealArg(v, what + name); };
  auto count = [&](const py::handle& v, const char* name, int max) {
    return static_cast<int>(IntegerArg(v, what + name, 1, max));
  };
  LightFieldGeometry g;
  g.origin_z_m = real(origin_z, "origin_z"), g.window_left_m = real(window_left, "window_left");
  g.window_top_m = real(window_top, "window_top"), g.window_width_m = real(window_width, "window_width");
  g.window_height_m = real(window_height, "window_height");
  g.cols = count(cols, "cols", kMaxPixelsPerAxis), g.rows = count(rows, "rows", kMaxPixelsPerAxis);
  g.views_x = count(views_x, "views_x", kMaxViewsPerAxis);
  g.views_y = count(views_y, "views_y", kMaxViewsPerAxis);
  g.eyebox_width_m = real(eyebox_width, "eyebox_width"), g.eyebox_height_m = real(eyebox_height, "eyebox_height");
  CheckGeometryArgument(g, "LightFieldGeometry");
  return g;
}

void BindLightFieldGeometry(py::module_& m) {
  py::class_<LightFieldGeometry>(m, "LightFieldGeometry",
                                 "Two-plane parameterization: views on the pupil plane, pixels on the origin plane (m)")
      .def(py::init(&GeometryArguments), py::kw_only(), py::arg("origin_z") = 1.0, py::arg("window_left") = -0.5,
           py::arg("window_top") = 0.5, py::arg("window_width") = 1.0, py::arg("window_height") = 1.0,
           py::arg("cols") = 1, py::arg("rows") = 1, py::arg("views_x") = 1, py::arg("views_y") = 1,
           py::arg("eyebox_width") = 6e-3, py::arg("eyebox_height") = 6e-3)
      .def_readwrite("origin_z", &LightFieldGeometry::origin_z_m)
      .def_readwrite("window_left", &LightFieldGeometry::window_left_m)
      .def_readwrite("window_top", &LightFieldGeometry::window_top_m)
      .def_readwrite("window_width", &LightFieldGeometry::window_width_m)
      .def_readwrite("window_height", &LightFieldGeometry::window_height_m)
      .def_readwrite("cols", &LightFieldGeometry::cols)
      .def_readwrite("rows", &LightFieldGeometry::rows)
      .def_readwrite("views_x", &LightFieldGeometry::views_x)
      .def_readwrite("views_y", &LightFieldGeometry::views_y)
      .def_readwrite("eyebox_width", &LightFieldGeometry::eyebox_width_m)
      .def_readwrite("eyebox_height", &LightFieldGeometry::eyebox_height_m)
      .def_property_readonly(
          "shape", [](const LightFieldGeometry& g) { return py::tuple(py::cast(RgbShape(g))); },
          "(views, rows, cols, 3): the shape of LightField.rgb")
      .def("__repr__", [](const LightFieldGeometry& g) {
        return "<layerlab.LightFieldGeometry " + std::to_string(g.views_y) + " x " + std::to_string(g.views_x) +
               " views of " + std::to_string(g.cols) + " x " + std::to_string(g.rows) + ">";
      });
}

void BindLightFieldClass(py::module_& m) {
  py::class_<LightField, std::shared_ptr<LightField>>(m, "LightField", "Linear RGB radiance per ray, float32")
      .def(py::init([](const LightFieldGeometry& g) {
             CheckGeometryArgument(g, "LightField: geometry");
             return std::make_shared<LightField>(g);
           }),
           py::arg("geometry"), "A black light field")
      .def(py::init(&FromArray), py::arg("rgb"), py::arg("geometry"),
           "A light field holding a copy of `rgb`, shape geometry.shape = (views, rows, cols, 3)")
      .def_property_readonly(
          "geometry", [](const LightField& lf) { return lf.geometry; }, "(a copy)")
      .def_readwrite("scene", &LightField::scene, "free text of the manifest")
      .def_property_readonly(
          "rgb",
          [](py::object self) {
            const LightField& lf = self.cast<const LightField&>();
            return FloatView(RgbShape(lf.geometry), lf.rgb.data(), self);
          },
          "(views, rows, cols, 3) float32, a writable view of the light field's own buffer")
      .def_property_readonly(
          "depth",
          [](py::object self) -> py::object {
            const LightField& lf = self.cast<const LightField&>();
            if (lf.depth.empty()) return py::none();
            std::vector<py::ssize_t> shape = RgbShape(lf.geometry);
            shape.pop_back();
            return FloatView(shape, lf.depth.data(), self);
          },
          "(views, rows, cols) eye-space z in m of the first surface, or None")
      .def(
          "view",
          [](py::object self, int r, int c) {
            const LightField& lf = self.cast<const LightField&>();
            const LightFieldGeometry& g = lf.geometry;
            if (r < 0 || r >= g.views_y || c < 0 || c >= g.views_x)
              throw py::index_error("view (" + std::to_string(r) + ", " + std::to_string(c) + ") outside " +
                                    std::to_string(g.views_y) + " x " + std::to_string(g.views_x) + " views");
            return FloatView({g.rows, g.cols, 3}, lf.view(g.view_index(r, c)), self);
          },
          py::arg("row"), py::arg("col"), "(rows, cols, 3) view of one view, row r and column c of the eyebox")
      .def(
          "save",
          [](const LightField& lf, const py::object& folder) {
            const std::string path = PathArg(folder);
            // Never a folder that read_lightfield (and the command) would refuse.
            CheckArgument([&] { CheckLightFieldValues(lf, "LightField.save: rgb"); });
            py::gil_scoped_release release;
            return WriteLightField(lf, path);
          },
          py::arg("folder"),
          "Writes the folder (docs/lightfield-format.md); returns the files written. Values that are not light "
          "(NaN, infinite, negative) are refused, as read_lightfield would refuse them")
      .def("__repr__", [](const LightField& lf) {
        const LightFieldGeometry& g = lf.geometry;
        return "<layerlab.LightField " + std::to_string(g.views_y) + " x " + std::to_string(g.views_x) + " views of " +
               std::to_string(g.cols) + " x " + std::to_string(g.rows) + ">";
      });
}

// Reading, rendering and suggesting light fields.
void BindLightFieldFunctions(py::module_& m) {
  m.def(
      "read_lightfield",
      [](const py::object& folder, bool load_depth) {
        const std::string path = PathArg(folder);
        py::gil_scoped_release release;
        return std::make_shared<LightField>(ReadLightField(path, {.load_depth = load_depth}));
      },
      py::arg("folder"), py::arg("load_depth") = true, "Reads a light-field folder (lightfield.json and views/)");
  m.def(
      "render_target",
      [](const py::object& target_scene) -> std::shared_ptr<LightField> {
        const std::string path = PathArg(target_scene);
#if LAYERLAB_WITH_EMBREE
        py::gil_scoped_release release;
        const TargetScene scene = LoadTarget(path);
        return std::make_shared<LightField>(RenderTarget(scene));
#else
        throw Error(path + ": rendering a target scene needs Embree (this build has LAYERLAB_WITH_EMBREE=OFF)");
#endif
      },
      py::arg("target_scene"), "Renders a target scene (docs/target-format.md) with Embree");
  m.def(
      "display_geometry",
      [](const DisplaySystem& system, const py::handle& origin_diopters) {
        const double d = RealArg(origin_diopters, "display_geometry: origin_diopters");
        LightFieldGeometry g;
        CheckArgument([&] { g = DisplayLightFieldGeometry(system, d); });
        CheckGeometryArgument(g, "display_geometry: origin_diopters " + py::repr(origin_diopters).cast<std::string>() +
                                     " gives a geometry");
        return g;
      },
      py::arg("system"), py::arg("origin_diopters") = -1.0,
      "The light-field geometry the display suggests (its field of view, farthest layer's pixels, the eye's views)");
}

}  // namespace

void BindLightField(py::module_& m) {
  BindLightFieldGeometry(m);
  BindLightFieldClass(m);
  BindLightFieldFunctions(m);
}

}  // namespace layerlab::python
