#include "systems/diffraction.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <vector>

#include <unsupported/Eigen/FFT>

#include "framework/error.h"

namespace layerlab {
namespace {

// The smallest n' >= n whose prime factors are 2, 3 and 5 (fast for kissfft).
int FastSize(int n) {
  for (int m = std::max(n, 1);; ++m) {
    int r = m;
    for (int p : {2, 3, 5})
      while (r % p == 0) r /= p;
    if (r == 1) return m;
  }
}

// A line of `n` complex values stepped by `stride`, transformed in place.
void Transform(Eigen::FFT<double>& fft, std::complex<double>* data, int n, int stride, bool inverse,
               std::vector<std::complex<double>>& in, std::vector<std::complex<double>>& out) {
  in.resize(n);
  for (int k = 0; k < n; ++k) in[k] = data[size_t(k) * stride];
  if (inverse)
    fft.inv(out, in);
  else
    fft.fwd(out, in);
  for (int k = 0; k < n; ++k) data[size_t(k) * stride] = out[k];
}

}  // namespace

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
  const int pad = std::max(8, static_cast<int>(std::ceil(20 * 1.22 * longest / pupil_diameter / grid.resolution)));
  const int nx = FastSize(grid.cols + 2 * pad), ny = FastSize(grid.rows + 2 * pad);
  Eigen::FFT<double> fft;
  std::vector<std::complex<double>> field(size_t(nx) * ny), in, out;
  for (int c = 0; c < 3; ++c) {
    for (int i = 0; i < ny; ++i)
      for (int j = 0; j < nx; ++j) {
        // Edge values outward from the image (centered in the padded grid); the rest wraps.
        int si = std::clamp(i - pad, 0, grid.rows - 1), sj = std::clamp(j - pad, 0, grid.cols - 1);
        if (i - pad >= grid.rows + pad) si = 0;
        if (j - pad >= grid.cols + pad) sj = 0;
        field[size_t(i) * nx + j] = image->at(si, sj, c);
      }
    for (int i = 0; i < ny; ++i) Transform(fft, &field[size_t(i) * nx], nx, 1, false, in, out);
    for (int j = 0; j < nx; ++j) Transform(fft, &field[j], ny, nx, false, in, out);
    for (int i = 0; i < ny; ++i) {
      const int ki = i <= ny / 2 ? i : i - ny;
      const double fy = ki / (ny * grid.resolution);
      for (int j = 0; j < nx; ++j) {
        const int kj = j <= nx / 2 ? j : j - nx;
        field[size_t(i) * nx + j] *=
            DiffractionOtf(shape, pupil_diameter, wavelengths[c], kj / (nx * grid.resolution), fy);
      }
    }
    for (int j = 0; j < nx; ++j) Transform(fft, &field[j], ny, nx, true, in, out);
    for (int i = 0; i < grid.rows; ++i) {
      Transform(fft, &field[size_t(i + pad) * nx], nx, 1, true, in, out);
      for (int j = 0; j < grid.cols; ++j)
        image->pixels[(size_t(i) * grid.cols + j) * 3 + c] =
            static_cast<float>(field[size_t(i + pad) * nx + j + pad].real());
    }
  }
}

void ApplyEyeOptics(const EyeModel& eye, const RetinaGrid& grid, Image* image) {
  if (eye.diffraction) ApplyDiffraction(eye.pupil_shape, eye.pupil_diameter, eye.channel_wavelengths, grid, image);
}

}  // namespace layerlab
