// The shipped catalogue of optical materials: refractive index per wavelength
// from each manufacturer's (or the measuring paper's) dispersion formula.
//
// Every entry is a Sellmeier formula in micrometers,
//   n^2(lambda) - 1 = sum_i B_i lambda^2 / (lambda^2 - C_i)     (lambda in um, C_i in um^2),
// with the wavelength range its source states; outside that range Index()
// throws instead of extrapolating. Indices are relative to air, as the Schott
// catalogue's are, so "air" is exactly 1 (not the absolute index of air).
//
// Sources (coefficients, ranges, nd and vd copied from them):
//   Schott glasses (N-BK7, N-SF11, N-F2, N-LAK22, N-SF5, N-BAF10, SF5): the
//     SCHOTT optical glass catalogue, Zemax edition 2017-01-20b
//     (schott_2017-01-20b.agf, as mirrored by refractiveindex.info).
//   PMMA, PC (polycarbonate), E48R (ZEONEX E48R, a cyclo-olefin polymer):
//     N. Sultanova, S. Kasarova, I. Nikolov, "Dispersion properties of optical
//     polymers", Acta Physica Polonica A 116, 585-587 (2009), measured at 20 C,
//     one-term Sellmeier fit by M. Polyanskiy (refractiveindex.info), valid
//     0.4368 to 1.052 um.
#pragma once

#include <array>
#include <string>
#include <vector>

namespace layerlab::lenses {

// The Fraunhofer lines of the catalogues' nd, vd (meters).
inline constexpr double kLineD_m = 587.5618e-9;  // helium d
inline constexpr double kLineF_m = 486.1327e-9;  // hydrogen F
inline constexpr double kLineC_m = 656.2725e-9;  // hydrogen C
inline constexpr double kLineE_m = 546.0740e-9;  // mercury e

struct Material {
  std::string name;                         // the catalogue name, case-sensitive ("N-BK7")
  std::array<double, 3> sellmeier_b{};      // B_i (unused terms 0)
  std::array<double, 3> sellmeier_c_um2{};  // C_i in um^2
  double min_wavelength_m = 0;              // the source's validity range
  double max_wavelength_m = 0;
  std::string source;       // where the coefficients come from
  double catalogue_nd = 0;  // the source's published nd, vd (0: none published)
  double catalogue_vd = 0;

  bool IsAir() const { return name == "air"; }
  // n at `wavelength_m`; throws layerlab::Error naming the material and its
  // range when the wavelength lies outside it.
  double Index(double wavelength_m) const;
};

// The catalogue entry named `name`; throws layerlab::Error listing the known
// names when there is none.
const Material& FindMaterial(const std::string& name);

// Every catalogue name, in catalogue order.
std::vector<std::string> MaterialNames();

// Abbe number (n_d - 1) / (n_F - n_C) of `material` from its formula.
double AbbeNumber(const Material& material);

}  // namespace layerlab::lenses
