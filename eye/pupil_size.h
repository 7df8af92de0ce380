// Light-adapted pupil size: the unified formula of Watson and Yellott (2012),
// "A unified formula for light-adapted pupil size", J. Vision 12(10):12, Eq. 22:
//   F    = L a M(e)                      (L cd/m2, a field area deg2; M(1) = 0.1, M(2) = 1)
//   D_SD = 7.75 - 5.75 (F/846)^0.41 / ((F/846)^0.41 + 2)   (Stanley and Davies 1995, mm)
//   D_U  = D_SD + (y - 28.58) (0.02132 - 0.009562 D_SD)     (age y in years, 20 to 83)
#pragma once

namespace layerlab {

struct PupilAdaptation {
  double luminance_cd_m2 = 0;  // at the eye
  double field_area_deg2 = 0;  // the adapting field's area
  double age_years = 28.58;    // the formula's reference age, where the age term vanishes
  int eyes = 1;                // 1 (one eye sees the field) or 2
};

// D_U in meters. Throws layerlab::Error outside the formula's domain
// (luminance or area not positive, age outside 20 to 83, eyes not 1 or 2).
double WatsonYellottPupilDiameter(const PupilAdaptation& a);

}  // namespace layerlab
