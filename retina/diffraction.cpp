#include "layerlab/retina/diffraction.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <vector>

#include "layerlab/eye/spectral_filter.h"
#include "layerlab/framework/error.h"

namespace layerlab {

double DiffractionOtf(PupilShape shape, double pupil_diameter, double wavelength, double fx, double fy) {
  const double cutoff = pupil_diameter / wavelength;
  if (shape == PupilShape::kSquare)
    return std::max(0.0, 1 - std::abs(fx) / cutoff) * std::max(0.0, 1 - std::abs(fy) / cutoff);
  const double nu = std::hypot(fx, fy) / cutoff;
  if (nu >= 1) return 0;
  return 2 / std::numbers::pi * (std::acos(nu) - nu * std::sqrt(1 - nu * nu));
}

void ApplyDiffraction(PupilShape shape, double pupil_diameter, const std::array<double, 3>& wavelengths,
                      const RetinaGrid& grid, Image* image) {
  if (!(pupil_diameter > 0)) throw Error("diffraction needs a pupil larger than a pinhole");
  if (image->width != grid.cols || image->height != grid.rows || image->channels.size() != 3)
    throw Error("diffraction: the image is not an RGB image of the retina grid");
  const double longest = *std::max_element(wavelengths.begin(), wavelengths.end());
  // 20 Airy radii of edge values on every side: the PSF's energy beyond
  // them (under 1 %) wraps onto edge values, not onto the image's far side.
  const int pad = std::max(8, static_cast<int>(std::ceil(20 * 1.22 * longest / pupil_diameter / grid.resolution_rad)));
  const int nx = FastFftSize(grid.cols + 2 * pad), ny = FastFftSize(grid.rows + 2 * pad);
  std::vector<std::complex<double>> field(size_t(nx) * ny);
  for (int c = 0; c < 3; ++c) {
    for (int i = 0; i < ny; ++i)
      for (int j = 0; j < nx; ++j) {
        // Edge values outward from the image (centered in the padded grid); the rest wraps.
        int si = std::clamp(i - pad, 0, grid.rows - 1), sj = std::clamp(j - pad, 0, grid.cols - 1);
        if (i - pad >= grid.rows + pad) si = 0;
        if (j - pad >= grid.cols + pad) sj = 0;
        field[size_t(i) * nx + j] = image->at(si, sj, c);
      }
    FilterPeriodic(&field, nx, ny, grid.resolution_rad,
                   [&](double fx, double fy) { return DiffractionOtf(shape, pupil_diameter, wavelengths[c], fx, fy); });
    for (int i = 0; i < grid.rows; ++i)
      for (int j = 0; j < grid.cols; ++j)
        image->pixels[(size_t(i) * grid.cols + j) * 3 + c] =
            static_cast<float>(field[size_t(i + pad) * nx + j + pad].real());
  }
}

}  // namespace layerlab
