#include "layerlab/eye/spectral_filter.h"

#include <algorithm>

#include <unsupported/Eigen/FFT>

#include "layerlab/framework/error.h"

namespace layerlab {
namespace {

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

int FastFftSize(int n) {
  for (int m = std::max(n, 1);; ++m) {
    int r = m;
    for (int p : {2, 3, 5})
      while (r % p == 0) r /= p;
    if (r == 1) return m;
  }
}

void FilterPeriodic(std::vector<std::complex<double>>* field, int nx, int ny, double spacing,
                    const std::function<double(double fx, double fy)>& gain) {
  if (nx <= 0 || ny <= 0 || field->size() != size_t(nx) * ny) throw Error("a filtered field must hold nx x ny values");
  Eigen::FFT<double> fft;
  std::vector<std::complex<double>> in, out;
  std::complex<double>* f = field->data();
  for (int i = 0; i < ny; ++i) Transform(fft, f + size_t(i) * nx, nx, 1, false, in, out);
  for (int j = 0; j < nx; ++j) Transform(fft, f + j, ny, nx, false, in, out);
  for (int i = 0; i < ny; ++i) {
    const int ki = i <= ny / 2 ? i : i - ny;
    const double fy = ki / (ny * spacing);
    for (int j = 0; j < nx; ++j) {
      const int kj = j <= nx / 2 ? j : j - nx;
      f[size_t(i) * nx + j] *= gain(kj / (nx * spacing), fy);
    }
  }
  for (int j = 0; j < nx; ++j) Transform(fft, f + j, ny, nx, true, in, out);
  for (int i = 0; i < ny; ++i) Transform(fft, f + size_t(i) * nx, nx, 1, true, in, out);
}

}  // namespace layerlab
