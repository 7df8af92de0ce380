// The linear and multilinear maps of the forward model with their adjoints,
// for a loss of the caller's own (python/layerlab/torch.py wraps them as
// autograd Functions): DisplayOperator, patterns -> light field
// (solvers/display_jacobian.h), and RetinaOperator, light field -> retinal
// images per accommodation state (retina/retinal_operator.h).
#include <cmath>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "layerlab/analysis/retina_sweep.h"
#include "layerlab/framework/lightfield_checks.h"
#include "layerlab/framework/units.h"
#include "layerlab/python/src/arguments.h"
#include "layerlab/python/src/bindings.h"
#include "layerlab/python/src/display_args.h"
#include "layerlab/python/src/numpy_view.h"
#include "layerlab/retina/retina.h"
#include "layerlab/retina/retinal_operator.h"
#include "layerlab/solvers/display_jacobian.h"
#include "layerlab/solvers/retinal_objective.h"
#include "layerlab/systems/lc_response.h"
#include "layerlab/systems/panel_diffraction.h"
#include "layerlab/systems/source_spread.h"

namespace py = pybind11;

namespace layerlab::python {
namespace {

// Raises ArgumentError at the first value that is not finite, naming its index in an array of `shape`.
void RequireFinite(const float* values, const std::vector<py::ssize_t>& shape, const std::string& what) {
  size_t n = 1;
  for (py::ssize_t d : shape) n *= static_cast<size_t>(d);
  for (size_t i = 0; i < n; ++i) {
    if (std::isfinite(values[i])) continue;
    std::string index;
    size_t rest = i;
    for (size_t d = shape.size(); d-- > 0;) {
      index = std::to_string(rest % shape[d]) + (index.empty() ? "" : ", ") + index;
      rest /= shape[d];
    }
    RaiseArgumentError(what + ": value at (" + index + ") is " + Repr(py::float_(values[i])) + "; must be finite");
  }
}

std::vector<py::ssize_t> LightFieldShape(const LightFieldGeometry& g) {
  return {static_cast<py::ssize_t>(g.view_count()), g.rows, g.cols, 3};
}

// A light field of geometry `g` from an array of its shape; finite values (any sign: a gradient is no light).
LightField LightFieldOf(const py::handle& value, const LightFieldGeometry& g, const std::string& what) {
  const auto a = FloatArrayOfShape(value, LightFieldShape(g), what, "(views, rows, cols, RGB)");
  RequireFinite(a.data(), LightFieldShape(g), what);
  LightField lf(g);
  std::copy(a.data(), a.data() + lf.rgb.size(), lf.rgb.begin());
  return lf;
}

std::optional<LightFieldGeometry> GeometryArg(const py::handle& value, const std::string& name) {
  if (value.is_none()) return std::nullopt;
  if (!py::isinstance<LightFieldGeometry>(value))
    throw py::type_error(name + ": expected a layerlab.LightFieldGeometry or None, got " + TypeName(value));
  return value.cast<LightFieldGeometry>();
}

// A list or tuple (one pattern per layer): TypeError otherwise.
py::sequence PatternListArg(const py::handle& value, const std::string& name) {
  if (!py::isinstance<py::list>(value) && !py::isinstance<py::tuple>(value))
    throw py::type_error(name + ": expected a list of (rows, cols, 3) arrays, one per layer, got " + TypeName(value));
  return py::reinterpret_borrow<py::sequence>(value);
}

class DisplayOperator {
 public:
  DisplayOperator(std::shared_ptr<DisplaySystem> system, const std::optional<LightFieldGeometry>& geometry,
                  const std::string& sampling, bool panel_diffraction, bool lc_response)
      : system_(std::move(system)) {
    const ModelRays rays = ModelRaysArg(*system_, geometry, sampling, "DisplayOperator");
    py::gil_scoped_release release;
    model_ = std::make_unique<DisplayModel>(*system_, rays.geometry, rays.sampling);
    diffraction_ = SeenKernels(*system_, panel_diffraction);
    response_ = lc_response && ResponseMatters(*system_);
    jacobian_ = std::make_unique<DisplayJacobian>(*model_, &diffraction_, response_);
  }

  py::array_t<float> Forward(const py::object& patterns) {
    const Patterns t =
        PatternsOf(PatternListArg(patterns, "DisplayOperator.forward: patterns"), "DisplayOperator.forward");
    LightField light;
    {
      py::gil_scoped_release release;
      std::lock_guard<std::mutex> lock(mutex_);
      light = jacobian_->Light(t);
      jacobian_->Forget();  // t is this call's
    }
    return OwningArray(std::move(light.rgb), LightFieldShape(model_->geometry()));
  }

  py::list Adjoint(const py::object& patterns, const py::handle& gradient) {
    const Patterns t =
        PatternsOf(PatternListArg(patterns, "DisplayOperator.adjoint: patterns"), "DisplayOperator.adjoint");
    const LightField v = LightFieldOf(gradient, model_->geometry(), "DisplayOperator.adjoint: light_field_gradient");
    Patterns g;
    {
      py::gil_scoped_release release;
      std::lock_guard<std::mutex> lock(mutex_);
      g = jacobian_->Transposed(t, v);
    }
    py::list out;
    for (LayerPattern& p : g) out.append(OwningArray(std::move(p.rgb), {p.rows, p.cols, 3}));
    return out;
  }

  const std::shared_ptr<DisplaySystem>& system() const { return system_; }
  const LightFieldGeometry& geometry() const { return model_->geometry(); }
  bool diffracts() const { return !diffraction_.empty(); }
  bool responds() const { return response_; }

 private:
  // One (rows, cols, 3) array per layer, finite (values outside [0, 1] are allowed: an optimizer's step may
  // leave the range, and the maps are defined there).
  Patterns PatternsOf(const py::sequence& arrays, const std::string& what) const {
    return PatternArrays(*system_, arrays, what, what + ": ", [](const LayerPattern& p, const std::string& name) {
      RequireFinite(p.rgb.data(), {p.rows, p.cols, 3}, name);
    });
  }

  std::shared_ptr<DisplaySystem> system_;
  std::unique_ptr<DisplayModel> model_;
  std::vector<LayerDiffraction> diffraction_;
  bool response_ = false;
  std::unique_ptr<DisplayJacobian> jacobian_;
  std::mutex mutex_;  // the Jacobian's buffers: one call at a time
};

class RetinaOperator {
 public:
  RetinaOperator(std::shared_ptr<DisplaySystem> system, const std::vector<double>& accommodation,
                 std::optional<double> resolution_deg, const std::optional<LightFieldGeometry>& geometry,
                 const std::string& sampling)
      : system_(std::move(system)), accommodation_(accommodation) {
    const ModelRays rays = ModelRaysArg(*system_, geometry, sampling, "RetinaOperator");
    const LightFieldGeometry& g = rays.geometry;
    CheckArgument([&] { CheckAccommodationStates(accommodation, "RetinaOperator: accommodation"); });
    // The field the light field's window spans (one sample per pixel), checked with the resolution before a
    // grid of that resolution is made (`layerlab retina`'s limits: CheckRetinaSampling).
    const RetinaGrid per_pixel = RetinalObjectiveGrid(g, 0.0);
    const double resolution = resolution_deg ? *resolution_deg : per_pixel.resolution_rad / kRadiansPerDegree;
    CheckArgument([&] {
      CheckRetinaSampling(per_pixel.cols * per_pixel.resolution_rad / kRadiansPerDegree,
                          per_pixel.rows * per_pixel.resolution_rad / kRadiansPerDegree, resolution,
                          "RetinaOperator: field", "RetinaOperator: resolution_deg");
    });
    const RetinaGrid grid = resolution_deg ? RetinalObjectiveGrid(g, resolution * kRadiansPerDegree) : per_pixel;
    std::vector<std::array<double, 3>> foci;
    for (double d : accommodation) foci.push_back(ChannelAccommodation(system_->eye, d));
    py::gil_scoped_release release;
    op_ = std::make_unique<RetinalOperator>(g, rays.sampling, grid, PupilSamples(system_->eye), foci);
  }

  py::array_t<float> Forward(const py::handle& light_field) {
    const LightField x = LightFieldOf(light_field, op_->geometry(), "RetinaOperator.forward: light_field");
    std::vector<std::vector<float>> images;
    {
      py::gil_scoped_release release;
      std::lock_guard<std::mutex> lock(mutex_);
      op_->Apply(x, &images);
    }
    std::vector<float> stacked;
    stacked.reserve(images.size() * op_->retinal_values());
    for (const std::vector<float>& image : images) stacked.insert(stacked.end(), image.begin(), image.end());
    return OwningArray(std::move(stacked), ImagesShape());
  }

  py::array_t<float> Adjoint(const py::handle& images) {
    const auto a =
        FloatArrayOfShape(images, ImagesShape(), "RetinaOperator.adjoint: images", "(states, rows, cols, RGB)");
    RequireFinite(a.data(), ImagesShape(), "RetinaOperator.adjoint: images");
    const size_t n = op_->retinal_values();
    std::vector<std::vector<float>> y(accommodation_.size());
    for (size_t s = 0; s < y.size(); ++s) y[s].assign(a.data() + s * n, a.data() + (s + 1) * n);
    LightField out(op_->geometry());
    {
      py::gil_scoped_release release;
      std::lock_guard<std::mutex> lock(mutex_);
      op_->ApplyTranspose(y, &out);
    }
    return OwningArray(std::move(out.rgb), LightFieldShape(op_->geometry()));
  }

  std::vector<py::ssize_t> ImagesShape() const {
    return {static_cast<py::ssize_t>(accommodation_.size()), op_->retina().rows, op_->retina().cols, 3};
  }
  const std::shared_ptr<DisplaySystem>& system() const { return system_; }
  const std::vector<double>& accommodation() const { return accommodation_; }
  const RetinalOperator& op() const { return *op_; }

 private:
  std::shared_ptr<DisplaySystem> system_;
  std::vector<double> accommodation_;
  std::unique_ptr<RetinalOperator> op_;
  std::mutex mutex_;  // Apply's work buffer: one call at a time
};

}  // namespace

void BindOperators(py::module_& m) {
  py::class_<DisplayOperator, std::shared_ptr<DisplayOperator>>(
      m, "DisplayOperator",
      "The display's forward model L(t) (patterns to light field, display-relative) and its Jacobian's transpose: "
      "the multilinear map the solvers minimize through (solvers/display_jacobian.h), subframes as branches")
      .def(py::init([](const py::object& system, const py::object& geometry, const py::object& sampling,
                       const py::object& panel_diffraction, const py::object& lc_response) {
             const std::string name = "DisplayOperator: ";
             return std::make_shared<DisplayOperator>(
                 HolderArg<DisplaySystem>(system, name + "system", "layerlab.System"),
                 GeometryArg(geometry, name + "geometry"), StringArg(sampling, name + "sampling"),
                 BoolArg(panel_diffraction, name + "panel_diffraction"), BoolArg(lc_response, name + "lc_response"));
           }),
           py::arg("system"), py::kw_only(), py::arg("geometry") = py::none(), py::arg("sampling") = "nearest",
           py::arg("panel_diffraction") = false, py::arg("lc_response") = false,
           "system: layerlab.System; geometry: layerlab.LightFieldGeometry or None, the light field's (default "
           "display_geometry(system)); sampling: str, 'nearest' (default) or 'bilinear'; panel_diffraction: bool "
           "(default False), lc_response: bool (default False): the solver options of these names (the panels' "
           "diffraction, the frame's average through their liquid-crystal response, where the display has them)")
      .def("forward", &DisplayOperator::Forward, py::arg("patterns"),
           "L(t): (views, rows, cols, 3) float32 from `patterns`, a list of one (rows, cols, 3) float array per layer "
           "(finite values)")
      .def("adjoint", &DisplayOperator::Adjoint, py::arg("patterns"), py::arg("light_field_gradient"),
           "J(t)^T v: the patterns' gradient of <v, L(t)>, one (rows, cols, 3) float32 array per layer; patterns as "
           "forward's, light_field_gradient v a (views, rows, cols, 3) float array (finite values)")
      .def_property_readonly("system", &DisplayOperator::system)
      .def_property_readonly("geometry", &DisplayOperator::geometry, "the light field's LightFieldGeometry")
      .def_property_readonly("panel_diffraction", &DisplayOperator::diffracts,
                             "whether the map includes the panels' diffraction (asked for, and a panel diffracts)")
      .def_property_readonly("lc_response", &DisplayOperator::responds,
                             "whether the map includes the panels' LC response (asked for, and it matters)")
      .def_property_readonly(
          "light_field_shape",
          [](const DisplayOperator& op) { return py::tuple(py::cast(LightFieldShape(op.geometry()))); },
          "(views, rows, cols, 3)")
      .def_property_readonly(
          "pattern_shapes",
          [](const DisplayOperator& op) {
            py::list shapes;
            for (const VirtualLayer& l : op.system()->layers) shapes.append(py::make_tuple(l.rows, l.cols, 3));
            return shapes;
          },
          "[(rows, cols, 3)] one per layer");

  py::class_<RetinaOperator, std::shared_ptr<RetinaOperator>>(
      m, "RetinaOperator",
      "The eye's retinal images of a light field, one per accommodation state, and the transpose: the retinal "
      "objective's linear operator A_a (retina/retinal_operator.h: the mean over the eye's pupil samples of the "
      "light field read along each ray through the in-focus point)")
      .def(py::init([](const py::object& system, const py::object& accommodation, const py::object& resolution_deg,
                       const py::object& geometry, const py::object& sampling) {
             const std::string name = "RetinaOperator: ";
             return std::make_shared<RetinaOperator>(
                 HolderArg<DisplaySystem>(system, name + "system", "layerlab.System"),
                 RealListArg(accommodation, name + "accommodation"),
                 resolution_deg.is_none() ? std::nullopt
                                          : std::optional<double>(RealArg(resolution_deg, name + "resolution_deg")),
                 GeometryArg(geometry, name + "geometry"), StringArg(sampling, name + "sampling"));
           }),
           py::arg("system"), py::arg("accommodation"), py::kw_only(), py::arg("resolution_deg") = py::none(),
           py::arg("geometry") = py::none(), py::arg("sampling") = "nearest",
           "system: layerlab.System; accommodation: list of float, the states (D); resolution_deg: float or None, "
           "deg per retinal sample (default: one sample per light-field pixel over its window); geometry: "
           "layerlab.LightFieldGeometry or None, the light field's (default display_geometry(system)); sampling: "
           "str, 'nearest' (default) or 'bilinear'")
      .def("forward", &RetinaOperator::Forward, py::arg("light_field"),
           "A L: (states, rows, cols, 3) float32 from light_field, a (views, rows, cols, 3) float array")
      .def("adjoint", &RetinaOperator::Adjoint, py::arg("images"),
           "sum_a A_a^T y_a: (views, rows, cols, 3) float32 from images, a (states, rows, cols, 3) float array")
      .def_property_readonly("system", &RetinaOperator::system)
      .def_property_readonly("accommodation", &RetinaOperator::accommodation, "the states (D)")
      .def_property_readonly(
          "geometry", [](const RetinaOperator& r) { return r.op().geometry(); }, "the light field's LightFieldGeometry")
      .def_property_readonly(
          "images_shape", [](const RetinaOperator& r) { return py::tuple(py::cast(r.ImagesShape())); },
          "(states, rows, cols, 3)")
      .def_property_readonly(
          "resolution_deg", [](const RetinaOperator& r) { return r.op().retina().resolution_rad / kRadiansPerDegree; },
          "deg per retinal sample");
}

}  // namespace layerlab::python
