// Structural similarity of two images of one channel: SSIM (Wang, Bovik,
// Sheikh and Simoncelli, "Image quality assessment: from error visibility to
// structural similarity", IEEE Trans. Image Processing 13(4), 2004) and
// MS-SSIM (Wang, Simoncelli and Bovik, "Multiscale structural similarity for
// image quality assessment", 37th Asilomar Conference, 2003).
//
// SSIM is the mean, over the image less a border of the window's radius, of
//   (2 mu_x mu_y + C1) (2 s_xy + C2) / ((mu_x^2 + mu_y^2 + C1) (s_x^2 + s_y^2 + C2)),
// the local means, variances and covariance weighted by a Gaussian of
// sigma 1.5 pixels truncated at 3.5 sigma (11 taps, radius 5), the image
// extended by reflection at its edges (d c b a | a b c d), population
// (co)variances, C1 = (0.01 R)^2 and C2 = (0.03 R)^2 for the data range R:
// scikit-image's structural_similarity(gaussian_weights=True, sigma=1.5,
// use_sample_covariance=False, data_range=R).
//
// MS-SSIM = l_5^w_5 prod_{j=1..5} cs_j^w_j over five scales, cs_j the mean of
// the second factor above at scale j, l_5 the mean of the first at the
// coarsest; each scale is the last one averaged over 2 x 2 pixels and
// subsampled by 2 (an odd last row or column dropped); w = (0.0448, 0.2856,
// 0.3001, 0.2363, 0.1333) from the paper. A negative cs_j or l_5 counts as 0,
// so MS-SSIM lies in [0, 1].
#pragma once

#include <vector>

#include "layerlab/framework/exr_image.h"

namespace layerlab {

// One channel, row-major, row 0 at the top.
struct Plane {
  int width = 0, height = 0;
  std::vector<double> values;
  double at(int row, int col) const { return values[static_cast<size_t>(row) * width + col]; }
};

// The smallest side MS-SSIM takes: its coarsest scale must hold the window.
inline constexpr int kMsSsimMinSide = 11 * 16;

// Throw layerlab::Error naming what is wrong: planes of other sizes, a side
// shorter than the window (11; kMsSsimMinSide for MS-SSIM), a data range
// not above 0, a value that is not finite.
// With `weight` (a plane of the images' size, >= 0, not all 0; foveal_weight.h)
// every mean over the image is weighted by it (MS-SSIM: halved with the images).
double Ssim(const Plane& x, const Plane& y, double data_range, const Plane* weight = nullptr);
double MsSsim(const Plane& x, const Plane& y, double data_range, const Plane* weight = nullptr);
// Throws layerlab::Error, naming `metric`, for a weight of another size, one negative or not finite, or all 0.
void CheckWeight(const Plane& image, const Plane* weight, const char* metric);

// The luminance of a linear RGB image in display-relative units (Rec. 709
// primaries: Y = 0.2126 R + 0.7152 G + 0.0722 B), encoded by the sRGB
// transfer curve (IEC 61966-2-1: 12.92 Y up to 0.0031308, else
// 1.055 Y^(1/2.4) - 0.055, continued above 1), the encoding the metrics
// compare in, data range 1. A negative or undefined value is refused, naming its pixel (row, col).
Plane EncodedLuminance(const Image& image);
// That transfer curve applied to a plane of linear luminance (>= 0), in place.
void EncodeLuminance(Plane* linear);

}  // namespace layerlab
