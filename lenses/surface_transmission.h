// The power transmittance of one refracting surface for unpolarized light,
// T = 1 - (Rs + Rp) / 2, from the angle of incidence and the indices n1
// (before) and n2 (after) the trace already has, for a bare (uncoated)
// surface or one carrying an anti-reflection coating.
//
//  - Uncoated: the Fresnel equations, with cos_i in medium 1 and cos_t in
//    medium 2 (n1 sin_i = n2 sin_t):
//      rs = (n1 cos_i - n2 cos_t) / (n1 cos_i + n2 cos_t),
//      rp = (n2 cos_i - n1 cos_t) / (n2 cos_i + n1 cos_t),   R = r^2.
//  - Quarter-wave single layer: a film of index n_c (non-dispersive) and
//    physical thickness lambda_0 / (4 n_c) (a quarter wave at normal incidence
//    at the design wavelength lambda_0), by its characteristic matrix for s
//    and p (Macleod, Thin-Film Optical Filters, ch. 2): phase
//    delta = 2 pi n_c d cos_c / lambda, tilted admittances eta = n cos for s
//    and n / cos for p, [B C] = [[cos delta, i sin delta / eta_c],
//    [i eta_c sin delta, cos delta]] [1 eta_2], r = (eta_1 - C/B) / (eta_1 + C/B).
//    At lambda_0 and normal incidence R = ((n1 n2 - n_c^2) / (n1 n2 + n_c^2))^2.
//    A lossless film reflects the same from either side, so the side of the
//    surface that carries it does not matter.
//  - Stated reflectance: a vendor's figure (e.g. Thorlabs -A, "Ravg < 0.5 %
//    over 400-700 nm"), taken as R at every angle and wavelength.
// No absorption in the coating; reflected light is lost (no ghost paths).
#pragma once

namespace layerlab::lenses {

struct Coating {
  enum class Kind {
    kUncoated,           // bare surface: Fresnel
    kQuarterWave,        // single layer, a quarter wave thick at design_wavelength_m
    kStatedReflectance,  // the vendor's residual reflectance, every angle and wavelength
  };
  Kind kind = Kind::kUncoated;
  double index = 0.0;                // kQuarterWave: the film's index (MgF2: 1.38)
  double design_wavelength_m = 0.0;  // kQuarterWave
  double reflectance = 0.0;          // kStatedReflectance: R in [0, 1)
};

// Power reflectances for s and p polarization.
struct Reflectance {
  double s = 0.0;
  double p = 0.0;
  double Unpolarized() const { return 0.5 * (s + p); }
};

// `cos_i` = |cos| of the angle of incidence in medium 1 (0 < cos_i <= 1).
// Total internal reflection gives R = 1.
Reflectance UncoatedReflectance(double n1, double n2, double cos_i);
Reflectance QuarterWaveReflectance(double n1, double n2, double cos_i, double film_index, double design_wavelength_m,
                                   double wavelength_m);

// 1 - R_unpolarized of `coating` on the surface between n1 and n2.
double SurfaceTransmittance(const Coating& coating, double n1, double n2, double cos_i, double wavelength_m);

}  // namespace layerlab::lenses
