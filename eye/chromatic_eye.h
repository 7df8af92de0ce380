// Longitudinal chromatic aberration of the eye: the chromatic eye of Thibos,
// Ye, Zhang and Bradley (1992), "The chromatic eye: a new reduced-eye model
// of ocular chromatic aberration in humans", Appl. Opt. 31:3594. Its
// refractive error at wavelength lambda (micrometers) is
//   Rx(lambda) = p - q / (lambda - c),  p = 1.68524, q = 0.63346, c = 0.21410 (D),
// negative where the eye is myopic (short wavelengths focus in front of the retina).
#pragma once

namespace layerlab {

// Rx(lambda) above, lambda in meters; D.
double ThibosRefraction(double wavelength);

// The defocus a channel at `wavelength` adds to the accommodation when the
// eye focuses `reference_wavelength` at it (D, both in meters): the eye's
// excess power there, Rx(reference) - Rx(wavelength). Positive for short
// wavelengths: blue focuses nearer than the reference.
double ThibosDefocus(double wavelength, double reference_wavelength);

}  // namespace layerlab
