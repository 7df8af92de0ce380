// layerlab.srgb: linear light to the 8-bit sRGB codes the PNGs hold
// (framework/srgb_code.h), so that a script shows a retinal image or a
// pattern without gamma code of its own.
#include <cmath>
#include <string>

#include <pybind11/numpy.h>

#include "layerlab/framework/srgb_code.h"
#include "layerlab/python/src/arguments.h"
#include "layerlab/python/src/bindings.h"

namespace layerlab::python {

namespace py = pybind11;

void BindSrgb(py::module_& m) {
  m.def(
      "srgb",
      [](const py::array_t<float, py::array::c_style | py::array::forcecast>& image, double white) {
        if (!(white > 0) || !std::isfinite(white))
          RaiseArgumentError("srgb: white: " + std::to_string(white) + " is not a finite value > 0");
        py::array_t<uint8_t> codes(std::vector<py::ssize_t>(image.shape(), image.shape() + image.ndim()));
        const float* in = image.data();
        uint8_t* out = codes.mutable_data();
        const py::ssize_t n = image.size();
        {
          py::gil_scoped_release release;
          for (py::ssize_t k = 0; k < n; ++k) out[k] = SrgbCode(in[k] / white);
        }
        return codes;
      },
      py::arg("image"), py::arg("white") = 1.0,
      "The 8-bit sRGB codes (IEC 61966-2-1) of linear light, `image` / `white` clamped to [0, 1] (NaN to 0): a "
      "uint8 array of the image's shape, the codes layerlab's PNGs hold. A retinal image is display-relative, "
      "so white=1 shows the display's white as white.");
}

}  // namespace layerlab::python
