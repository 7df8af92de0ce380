// A periodic 2D field filtered in frequency: its discrete Fourier transform
// times a real gain, transformed back (kissfft through Eigen's FFT, in
// double). What diffraction at the pupil (retina/diffraction.h) and the
// retinal objective's contrast-sensitivity weighting
// (solvers/retinal_objective.h) both do to a retinal image.
#pragma once

#include <complex>
#include <functional>
#include <vector>

namespace layerlab {

// The smallest n' >= n whose prime factors are 2, 3 and 5 (fast for kissfft).
int FastFftSize(int n);

// The 2D discrete Fourier transform of nx x ny values, row after row, in
// place: X[k] = sum_n x[n] exp(-2 pi i k.n / N), or with `inverse` the
// inverse, exp(+2 pi i k.n / N) summed without the 1 / (nx ny).
void Fft2d(std::vector<std::complex<double>>* field, int nx, int ny, bool inverse);

// The 2D transform of real images of nx x ny values (nx even), row after
// row, to their half spectra (ny rows of nx / 2 + 1 frequencies 0 to nx / 2)
// and back, in float; rows and columns are shared among the OpenMP threads.
class RealFft2d {
 public:
  RealFft2d(int nx, int ny);
  int nx() const { return nx_; }
  int ny() const { return ny_; }
  int half() const { return nx_ / 2 + 1; }
  void Forward(const float* image, std::complex<float>* spectrum) const;
  // The inverse, scaled by 1 / (nx ny); `spectrum` is overwritten.
  void Inverse(std::complex<float>* spectrum, float* image) const;

 private:
  int nx_, ny_;
};

// `field` holds nx x ny values, row after row, periodic in both directions
// with sample spacing `spacing`; each frequency (fx, fy), in cycles per unit
// of spacing (|f| up to 1 / (2 spacing)), is multiplied by gain(fx, fy).
// In place. With a gain even in fx and fy a real field stays real.
void FilterPeriodic(std::vector<std::complex<double>>* field, int nx, int ny, double spacing,
                    const std::function<double(double fx, double fy)>& gain);

}  // namespace layerlab
