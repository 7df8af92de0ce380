// ssim, ms_ssim, csf_jnd: the perceptual metrics of metrics/ on 2-D NumPy arrays (docs/metrics.md).
#include <string>

#include <pybind11/numpy.h>

#include "layerlab/metrics/csf_jnd.h"
#include "layerlab/metrics/ssim.h"
#include "layerlab/python/src/arguments.h"
#include "layerlab/python/src/bindings.h"

namespace layerlab::python {
namespace {

namespace py = pybind11;

Plane PlaneOf(const py::array_t<double, py::array::c_style | py::array::forcecast>& a, const char* name) {
  if (a.ndim() != 2)
    RaiseArgumentError(std::string(name) + ": a 2-D array (rows, cols) of one channel, not " +
                       std::to_string(a.ndim()) + "-D");
  Plane p{static_cast<int>(a.shape(1)), static_cast<int>(a.shape(0)), {}};
  p.values.assign(a.data(), a.data() + a.size());
  return p;
}

template <double (*metric)(const Plane&, const Plane&, double, const Plane*)>
double Metric(const py::array_t<double, py::array::c_style | py::array::forcecast>& x,
              const py::array_t<double, py::array::c_style | py::array::forcecast>& y, double data_range) {
  const Plane a = PlaneOf(x, "x"), b = PlaneOf(y, "y");
  double value = 0;
  CheckArgument([&] {
    py::gil_scoped_release release;
    value = metric(a, b, data_range, nullptr);
  });
  return value;
}

double Jnd(const py::array_t<double, py::array::c_style | py::array::forcecast>& reference,
           const py::array_t<double, py::array::c_style | py::array::forcecast>& test, double pixel_deg,
           double minkowski_exponent) {
  const Plane a = PlaneOf(reference, "reference"), b = PlaneOf(test, "test");
  double value = 0;
  CheckArgument([&] {
    py::gil_scoped_release release;
    value = CsfJnd(a, b, {pixel_deg, minkowski_exponent, nullptr});
  });
  return value;
}

}  // namespace

void BindMetrics(py::module_& m) {
  m.def("ssim", &Metric<&Ssim>, py::arg("x"), py::arg("y"), py::arg("data_range") = 1.0,
        "SSIM of two 2-D arrays of one channel (Wang et al. 2004): a Gaussian window of sigma 1.5 pixels, reflected "
        "edges, population statistics; scikit-image's structural_similarity(gaussian_weights=True, "
        "use_sample_covariance=False). docs/metrics.md");
  m.def("ms_ssim", &Metric<&MsSsim>, py::arg("x"), py::arg("y"), py::arg("data_range") = 1.0,
        "MS-SSIM of two 2-D arrays of one channel (Wang et al. 2003): five scales, each the last averaged over 2 x 2 "
        "pixels and subsampled; at least 176 pixels on each side. docs/metrics.md");
  m.def("csf_jnd", &Jnd, py::arg("reference"), py::arg("test"), py::arg("pixel_deg"),
        py::arg("minkowski_exponent") = 4.0,
        "The difference of two luminance images (2-D arrays, cd/m2, pixel_deg degrees a pixel) weighted by Barten's "
        "contrast sensitivity and pooled by a Minkowski mean, in just-noticeable differences: a full-field grating "
        "at its threshold scores 1. docs/metrics.md");
}

}  // namespace layerlab::python
