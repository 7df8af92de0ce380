// Diffraction at the eye's pupil: the incoherent diffraction-limited optical
// transfer function, applied to a retinal image per channel at the channel's
// wavelength (Goodman, Introduction to Fourier Optics, 6.3). With cutoff
// f_c = D / lambda cycles per radian and nu = f / f_c:
//   round pupil of diameter D: OTF = (2 / pi) (acos nu - nu sqrt(1 - nu^2)), PSF the Airy
//     pattern [2 J1(x) / x]^2, x = pi D theta / lambda, first zero at 1.22 lambda / D;
//   square pupil of side D: OTF = (1 - |nu_x|) (1 - |nu_y|), PSF sinc^2 in x times in y,
//     first zeros at lambda / D.
#pragma once

#include <array>

#include "layerlab/elements/element.h"
#include "layerlab/framework/exr_image.h"
#include "layerlab/retina/retina.h"

namespace layerlab {

// The OTF above at frequency (fx, fy) in cycles per radian.
double DiffractionOtf(PupilShape shape, double pupil_diameter, double wavelength, double fx, double fy);

// Convolves each channel c of `image` (on `grid`) with the pupil's
// diffraction PSF at wavelengths[c]: a 2D FFT of the image, extended by its
// edge values far enough that the wrap-around is below 1e-4 of the PSF's
// energy, times the OTF, back. A pinhole (diameter 0) is refused.
void ApplyDiffraction(PupilShape shape, double pupil_diameter, const std::array<double, 3>& wavelengths,
                      const RetinaGrid& grid, Image* image);

}  // namespace layerlab
