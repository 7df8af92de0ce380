// The contrast sensitivity of the human eye by Barten's physical model
// (P. G. J. Barten, "Contrast Sensitivity of the Human Eye and Its Effects on
// Image Quality", SPIE 1999, eq. 3.26; "Formula for the contrast sensitivity
// of the human eye", Proc. SPIE 5294, 2003): for a sinusoidal grating of
// u cycles per degree on a field of X0 x Y0 degrees at luminance L,
//   S(u) = (M_opt(u) / k) / sqrt((2 / T) (1 / (X Y)) (1 / (eta p E) + Phi0 / (1 - exp(-(u / u0)^2)))),
//   M_opt(u) = exp(-2 pi^2 sigma^2 u^2),  sigma = sqrt(sigma0^2 + (C_ab d)^2) (degrees),
//   X = (1 / X0^2 + 1 / X_max^2 + u^2 / N_max^2)^(-1/2), and Y alike,
//   E = (pi d^2 / 4) L (1 - (d / 9.7)^2 + (d / 12.4)^4) Trolands (Stiles-Crawford corrected),
//   d = 5 - 3 tanh(0.4 ln(L X0 Y0 / 40^2)) mm (the pupil for L and the field),
// with the standard observer's constants k = 3, T = 0.1 s, X_max = 12 deg,
// N_max = 15 cycles, eta = 0.03, p = 1.2274e6 photons / (s deg^2 Td),
// Phi0 = 3e-8 s deg^2, u0 = 7 cpd, sigma0 = 0.5 arcmin, C_ab = 0.08 arcmin / mm.
// Binocular viewing, as Barten fits it (one eye alone sees sqrt(2) less).
// S is 1 / the modulation threshold; S(0) = 0 (a uniform change is no grating).
#pragma once

#include <optional>

namespace layerlab {

struct BartenConditions {
  double luminance_cd_m2 = 100;               // L, the mean luminance the eye adapts to
  double field_x_deg = 10, field_y_deg = 10;  // X0, Y0
  std::optional<double> pupil_diameter_mm;    // d; empty: Barten's formula for L and the field
};

// Barten's pupil diameter (mm) for the conditions (their pupil_diameter_mm ignored).
double BartenPupilDiameterMm(const BartenConditions& c);
// The retinal illuminance (Trolands) of luminance L through a pupil of d mm, Stiles-Crawford corrected.
double RetinalIlluminanceTrolands(double luminance_cd_m2, double pupil_diameter_mm);
// S(u) above; u >= 0 in cycles per degree. Throws layerlab::Error naming a value not above 0.
double BartenContrastSensitivity(double cycles_per_degree, const BartenConditions& c);

}  // namespace layerlab
