// ssim, ms_ssim: the perceptual metrics of metrics/ on 2-D NumPy arrays (docs/metrics.md).
#include <string>

#include <pybind11/numpy.h>

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

template <double (*metric)(const Plane&, const Plane&, double)>
double Metric(const py::array_t<double, py::array::c_style | py::array::forcecast>& x,
              const py::array_t<double, py::array::c_style | py::array::forcecast>& y, double data_range) {
  const Plane a = PlaneOf(x, "x"), b = PlaneOf(y, "y");
  double value = 0;
  CheckArgument([&] {
    py::gil_scoped_release release;
    value = metric(a, b, data_range);
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
}

}  // namespace layerlab::python
