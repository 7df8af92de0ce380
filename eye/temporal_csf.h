// The eye's sensitivity to flicker: the temporal contrast sensitivity of a
// uniform disc whose luminance is modulated sinusoidally at w Hz, by
// Barten's spatio-temporal model (P. G. J. Barten, "Contrast Sensitivity of
// the Human Eye and Its Effects on Image Quality", SPIE 1999, ch. 5) with the
// high-temporal-frequency fit of A. Bozorgian, M. Ashraf and R. Mantiuk,
// "Spatiotemporal contrast sensitivity functions: predictions for the
// critical flicker frequency", Electronic Imaging 36 (HVEI), 2024, for
// a disc stimulus (Barten's edge rule: the disc's first spatial harmonic,
// its third from 2.5 deg of sigma; no optical MTF), on the nasal meridian:
//   S(w) = sqrt(2) (1 / (2 k)) sqrt(X Y T / (Phi_photon + Phi0 / M_lat(w)^2)),
//   M_lat(w) = H1(w) (1 - H2(w) F(u)),  H_i(w) = (1 + (2 pi w tau_i)^2)^(-n_i / 2),
//   tau1 = tau10 / (1 + 0.55 ln(1 + (1 + D)^0.6 E rf / t)),  tau2 = tau20 / (1 + 0.37 ln(1 + (1 + D / 3.2)^5 E / 120)),
// with E the retinal illuminance (Trolands, Stiles-Crawford corrected) of
// the pupil d = 5 - 3 tanh(0.4 log10(L X0^2 / 40^2)) mm (that fit's own
// pupil: log10, where eye/barten_csf.h follows colour-science's natural
// log), the ganglion-cell densities of Watson (2014) and the fit's constants
// k = 8.36831, u0 = 2.44734 cpd, tau10 = 0.0334009 s, tau20 = 0.0477005 s,
// t = 1.32776, k_nas = 0.171344, n1 = 7, n2 = 4, T = 0.1 s, X_max0 = 12 deg,
// N_max = 15, eta0 = 0.03, Phi00 = 3e-8 s deg^2. S is 1 / the threshold
// modulation: a sinusoidal flicker of modulation m is visible where m S(w) > 1.
// The critical flicker frequency of modulation m is the highest w where
// m S(w) >= 1 (for m = 1, the CFF proper); it rises with log luminance
// (Ferry-Porter) and log area (Granit-Harper), as tests/temporal_csf_test.cpp
// checks against the psychophysics.
#pragma once

namespace layerlab {

struct FlickerConditions {
  double luminance_cd_m2 = 100;  // the disc's mean luminance
  double area_deg2 = 4;          // the disc's area (a disc of 2.26 deg diameter by default)
  double eccentricity_deg = 0;   // its centre's angle from the gaze
};

// S(w) above, w >= 0 in Hz. Throws layerlab::Error naming a value out of range (luminance and area not above
// 0, eccentricity negative, frequency negative; any not finite).
double TemporalContrastSensitivity(double hz, const FlickerConditions& c);
// The highest frequency (Hz) at which a flicker of modulation `m` (0 < m; 1: full modulation) is visible,
// to 0.01 Hz; 0 when it is visible at none. Throws as above, and for m not above 0.
double CriticalFlickerFrequency(const FlickerConditions& c, double modulation = 1);

}  // namespace layerlab
