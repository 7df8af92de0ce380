// The eye's monochromatic wavefront aberration as Zernike polynomials in the
// OSA/ANSI convention (ANSI Z80.28; Thibos et al. 2002, "Standards for
// reporting the optical aberrations of eyes"): single index j = (n (n + 2) + m) / 2,
// Z_j = N R_n^|m|(rho) cos(m theta) for m >= 0 and N R_n^|m|(rho) sin(|m| theta)
// for m < 0, N = sqrt(2 (n + 1)) (sqrt(n + 1) for m = 0), theta counterclockwise
// from eye-space x (right), rho = r / (measurement pupil radius).
//
// In the pupil-sampled retina (retina.h) the ray from pupil point u leaves
// along the ideal eye's direction minus the wavefront's slope there, grad W(u)
// (the transverse ray aberration in tan units): an excess power P is
// W = P r^2 / 2, so pure defocus c_4 = c is the power 4 sqrt(3) c / R^2
// (16 sqrt(3) c / p^2, c in um and p in mm giving D). The wavefront is one
// physical surface: at an eye pupil other than the measurement pupil it is
// evaluated at rho = r / R_measured, which is what rescaling the coefficients
// to the eye's pupil does (a larger eye pupil extrapolates it).
#pragma once

#include <string>
#include <vector>

namespace layerlab {

inline constexpr int kMaxZernikeIndex = 27;  // through the sixth radial order

struct ZernikeOrder {
  int n = 0, m = 0;
};
ZernikeOrder ZernikeOrderOf(int j);  // OSA j to (n, m)

// Z_j at normalized pupil coordinates (x, y) = (r cos theta, r sin theta) / R.
double Zernike(int j, double x, double y);

struct Wavefront {
  std::vector<double> coefficients_m;  // m, index j; empty: aberration free
  double pupil_diameter_m = 0;         // m, the pupil they were measured (or scaled) at
  std::string source;                  // "" (given in the scene) or a population's name
  bool empty() const;
};

// W at pupil position (x, y) in meters, meters of optical path.
double WavefrontAt(const Wavefront& w, double x, double y);
// (dW/dx, dW/dy) at (x, y): the ray's deviation in tan units.
struct WavefrontSlope {
  double x = 0, y = 0;
};
WavefrontSlope WavefrontSlopeAt(const Wavefront& w, double x, double y);

// A population mean from the literature by name, or nullptr: "salmon_van_de_pol_2006"
// is the mean Z_12 (spherical aberration, Z(4,0)) of 2560 normal adult eyes,
// 0.13 um at a 6.0 mm pupil and 550 nm (Salmon and van de Pol 2006, J. Cataract
// Refract. Surg. 32:2064); the other modes' population means are taken as zero.
// The abstract gives 0.13 um as Z(4,0)'s mean absolute value; it is used as the
// signed mean (Z(4,0) is positive in most normal adult eyes), which overstates
// the mean by the share of eyes with negative spherical aberration.
const Wavefront* PopulationWavefront(const std::string& name);
std::vector<std::string> PopulationWavefrontNames();

}  // namespace layerlab
