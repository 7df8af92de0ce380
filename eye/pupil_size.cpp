#include "layerlab/eye/pupil_size.h"

#include <cmath>
#include <string>

#include "layerlab/framework/error.h"

namespace layerlab {

double WatsonYellottPupilDiameter(const PupilAdaptation& a) {
  if (!(a.luminance_cd_m2 > 0) || !(a.field_area_deg2 > 0))
    throw Error("pupil size: the luminance and the field area must be positive");
  if (!(a.age_years >= 20 && a.age_years <= 83)) throw Error("pupil size: the formula holds for ages 20 to 83");
  if (a.eyes != 1 && a.eyes != 2) throw Error("pupil size: eyes must be 1 or 2");
  const double flux = a.luminance_cd_m2 * a.field_area_deg2 * (a.eyes == 2 ? 1.0 : 0.1);
  const double s = std::pow(flux / 846, 0.41);
  const double stanley_davies = 7.75 - 5.75 * s / (s + 2);
  return 1e-3 * (stanley_davies + (a.age_years - 28.58) * (0.02132 - 0.009562 * stanley_davies));
}

}  // namespace layerlab
