// Bulk absorption of the catalogue's glasses: the internal transmittance (the
// fraction of the light that enters which reaches the exit face, reflections
// excluded) of a path of given length, per wavelength, from the manufacturer's
// published table.
//
// Data: SCHOTT publishes tau_i for 10 mm and 25 mm samples at 300 ... 2500 nm;
// the table here is the 25 mm one (3 decimals, the finer of the two), from
// the SCHOTT Zemax catalogue 2017-01-20b (its IT lines, the same release as
// the dispersion formulas), as mirrored by refractiveindex.info, which stores
// them as extinction coefficients k: tau_25mm = exp(-4 pi k 25 mm / lambda)
// recovers the published 3-decimal values to within 2e-5.
//
// Model: Beer-Lambert. Between two listed wavelengths the absorption
// coefficient alpha = -ln(tau_ref) / d_ref is interpolated linearly in
// wavelength (ln tau linear, so a path's tau is the geometric interpolation);
// a path of length L transmits tau = exp(-alpha L) = tau_ref^(L / d_ref).
// Outside the table's wavelengths the query throws instead of extrapolating.
//
// Materials without published data (the plastics PMMA, PC, E48R: their makers
// publish curves, not tables): absorption is not modelled, HasAbsorptionData()
// says so and AbsorptionPerMeter() returns 0 for them. Air: 0 (not modelled,
// negligible over a lens's gaps).
#pragma once

#include <string>

#include "layerlab/lenses/glass_catalog.h"

namespace layerlab::lenses {

// True when the catalogue has a published internal transmittance table for
// `material` (false for air and the plastics: their absorption is taken as 0).
bool HasAbsorptionData(const Material& material);

// The absorption coefficient alpha (1/m) of `material` at `wavelength_m`; 0
// for a material without data. Throws layerlab::Error naming the material and
// the table's range when the wavelength lies outside it.
double AbsorptionPerMeter(const Material& material, double wavelength_m);

// The internal transmittance exp(-alpha L) of a path `path_m` >= 0 long.
double InternalTransmittance(const Material& material, double wavelength_m, double path_m);

// The published table's reference thickness (25 mm) and where it comes from.
inline constexpr double kAbsorptionReferenceThickness_m = 25e-3;
std::string AbsorptionSource(const Material& material);

}  // namespace layerlab::lenses
