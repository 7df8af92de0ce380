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

// `field` holds nx x ny values, row after row, periodic in both directions
// with sample spacing `spacing`; each frequency (fx, fy), in cycles per unit
// of spacing (|f| up to 1 / (2 spacing)), is multiplied by gain(fx, fy).
// In place. With a gain even in fx and fy a real field stays real.
void FilterPeriodic(std::vector<std::complex<double>>* field, int nx, int ny, double spacing,
                    const std::function<double(double fx, double fy)>& gain);

}  // namespace layerlab
