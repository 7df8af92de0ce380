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

namespace {

void CheckField(const std::vector<std::complex<double>>& field, int nx, int ny) {
  if (nx <= 0 || ny <= 0 || field.size() != size_t(nx) * ny) throw Error("a 2D field must hold nx x ny values");
}

// The 2D transform with `fft`'s scaling: rows then columns forward, columns then rows back.
void TransformField(Eigen::FFT<double>& fft, std::complex<double>* f, int nx, int ny, bool inverse) {
  std::vector<std::complex<double>> in, out;
  auto rows = [&] {
    for (int i = 0; i < ny; ++i) Transform(fft, f + size_t(i) * nx, nx, 1, inverse, in, out);
  };
  auto columns = [&] {
    for (int j = 0; j < nx; ++j) Transform(fft, f + j, ny, nx, inverse, in, out);
  };
  if (inverse)
    columns(), rows();
  else
    rows(), columns();
}

}  // namespace

void Fft2d(std::vector<std::complex<double>>* field, int nx, int ny, bool inverse) {
  CheckField(*field, nx, ny);
  Eigen::FFT<double> fft;
  fft.SetFlag(Eigen::FFT<double>::Unscaled);
  TransformField(fft, field->data(), nx, ny, inverse);
}

void FilterPeriodic(std::vector<std::complex<double>>* field, int nx, int ny, double spacing,
                    const std::function<double(double fx, double fy)>& gain) {
  CheckField(*field, nx, ny);
  Eigen::FFT<double> fft;
  std::complex<double>* f = field->data();
  TransformField(fft, f, nx, ny, false);
  for (int i = 0; i < ny; ++i) {
    const int ki = i <= ny / 2 ? i : i - ny;
    const double fy = ki / (ny * spacing);
    for (int j = 0; j < nx; ++j) {
      const int kj = j <= nx / 2 ? j : j - nx;
      f[size_t(i) * nx + j] *= gain(kj / (nx * spacing), fy);
    }
  }
  TransformField(fft, f, nx, ny, true);
}

RealFft2d::RealFft2d(int nx, int ny) : nx_(nx), ny_(ny) {
  if (nx < 2 || ny < 1 || nx % 2 != 0) throw Error("a real 2D transform needs an even width and a height >= 1");
}

namespace {

// The columns [j, j + count) of a half spectrum (`half` columns, `rows` rows) transformed in place,
// gathered into contiguous lines a block at a time (rows read and written in order).
constexpr int kColumnBlock = 16;
void TransformColumns(Eigen::FFT<float>& fft, std::complex<float>* spectrum, int half, int rows, int j, int count,
                      bool inverse, std::vector<std::complex<float>>& lines, std::vector<std::complex<float>>& out) {
  lines.resize(size_t(count) * rows), out.resize(rows);
  for (int i = 0; i < rows; ++i)
    for (int b = 0; b < count; ++b) lines[size_t(b) * rows + i] = spectrum[size_t(i) * half + j + b];
  for (int b = 0; b < count; ++b) {
    std::complex<float>* line = lines.data() + size_t(b) * rows;
    if (inverse)
      fft.inv(out.data(), line, rows);
    else
      fft.fwd(out.data(), line, rows);
    std::copy(out.begin(), out.end(), line);
  }
  for (int i = 0; i < rows; ++i)
    for (int b = 0; b < count; ++b) spectrum[size_t(i) * half + j + b] = lines[size_t(b) * rows + i];
}

}  // namespace

void RealFft2d::Forward(const float* image, std::complex<float>* spectrum) const {
  const int half = this->half(), blocks = (half + kColumnBlock - 1) / kColumnBlock;
#pragma omp parallel
  {
    Eigen::FFT<float> fft;
    fft.SetFlag(Eigen::FFT<float>::HalfSpectrum);
#pragma omp for
    for (int i = 0; i < ny_; ++i) fft.fwd(spectrum + size_t(i) * half, image + size_t(i) * nx_, nx_);
    std::vector<std::complex<float>> lines, out;
#pragma omp for
    for (int k = 0; k < blocks; ++k)
      TransformColumns(fft, spectrum, half, ny_, k * kColumnBlock, std::min(kColumnBlock, half - k * kColumnBlock),
                       false, lines, out);
  }
}

void RealFft2d::Inverse(std::complex<float>* spectrum, float* image) const {
  const int half = this->half(), blocks = (half + kColumnBlock - 1) / kColumnBlock;
#pragma omp parallel
  {
    Eigen::FFT<float> fft;
    fft.SetFlag(Eigen::FFT<float>::HalfSpectrum);
    std::vector<std::complex<float>> lines, out;
#pragma omp for
    for (int k = 0; k < blocks; ++k)
      TransformColumns(fft, spectrum, half, ny_, k * kColumnBlock, std::min(kColumnBlock, half - k * kColumnBlock),
                       true, lines, out);
#pragma omp for
    for (int i = 0; i < ny_; ++i) fft.inv(image + size_t(i) * nx_, spectrum + size_t(i) * half, nx_);
  }
}

}  // namespace layerlab
