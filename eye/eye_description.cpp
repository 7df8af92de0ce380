#include "layerlab/eye/eye_description.h"

#include "layerlab/eye/chromatic_eye.h"
#include "layerlab/framework/units.h"

namespace layerlab {

namespace {

// "" for the eye on the axis looking ahead; else where it is and looks, and
// of a binocular pair which eye, and the vergence.
std::string PoseDescription(const EyeModel& eye) {
  const EyePose& pose = eye.pose;
  std::string text;
  auto mm = [](double m) { return FormatFixed(m * 1e3, 2); };
  auto deg = [](double rad) { return FormatFixed(rad * kDegreesPerRadian, 2); };
  if (eye.binocular) {
    const Binocular& b = *eye.binocular;
    text += std::string("; ") + (b.side < 0 ? "left" : "right") + " eye of a pair " + mm(b.ipd_m) + " mm apart (" +
            (b.shared_display ? "shared display" : "a display each") + ") fixating (" + mm(b.fixation_m[0]) + ", " +
            mm(b.fixation_m[1]) + ", " + mm(b.fixation_m[2]) + ") mm: vergence " +
            deg(VergenceAngle(b, pose.rotation_radius_m)) + " deg, " + FormatFixed(VergenceDiopters(b), 3) + " D";
  }
  if (pose.pupil_offset_m != std::array<double, 2>{0, 0})
    text += "; pupil offset " + mm(pose.pupil_offset_m[0]) + ", " + mm(pose.pupil_offset_m[1]) + " mm";
  if (!pose.straight_ahead())
    text += "; gaze " + deg(pose.gaze_rad[0]) + " deg right, " + deg(pose.gaze_rad[1]) +
            " deg up (centre of rotation " + mm(pose.rotation_radius_m) + " mm behind the pupil)";
  return text;
}

}  // namespace

std::string EyeModelLine(const EyeModel& eye) {
  const bool ideal = eye.chromatic_aberration == ChromaticAberration::kNone && !eye.pupil_auto &&
                     eye.wavefront.empty() && eye.diffraction == EyeDiffraction::kNone;
  std::string line = ideal ? "ideal eye (geometric optics): " : "physiological eye: ";
  line += FormatFixed(eye.pupil_diameter_m * 1e3, 2) + " mm " +
          (eye.pupil_shape == PupilShape::kSquare ? "square" : "round") + " pupil";
  if (eye.pupil_auto)
    line += " (auto: Watson & Yellott 2012 at " + FormatFixed(eye.pupil_luminance_used_cd_m2, 1) + " cd/m2 over " +
            FormatFixed(eye.pupil_field_area_used_deg2, 0) + " deg2, age " + FormatFixed(eye.pupil_auto->age_years, 2) +
            ", " + std::to_string(eye.pupil_auto->eyes) + (eye.pupil_auto->eyes == 1 ? " eye)" : " eyes)");
  if (eye.chromatic_aberration == ChromaticAberration::kThibos) {
    line += "; chromatic aberration Thibos 1992 re " + FormatFixed(eye.reference_wavelength_m * 1e9, 0) + " nm (R/G/B";
    for (int c = 0; c < 3; ++c)
      line +=
          (c ? " / " : " ") + FormatFixed(ThibosDefocus(eye.channel_wavelengths_m[c], eye.reference_wavelength_m), 3);
    line += " D)";
  }
  if (eye.chromatic_defocus_diopters != std::array<double, 3>{0, 0, 0})
    line += "; chromatic defocus " + FormatFixed(eye.chromatic_defocus_diopters[0], 3) + " / " +
            FormatFixed(eye.chromatic_defocus_diopters[1], 3) + " / " +
            FormatFixed(eye.chromatic_defocus_diopters[2], 3) + " D";
  if (!eye.wavefront.empty()) {
    line += "; wavefront " + (eye.wavefront.source.empty() ? std::string("Zernike") : eye.wavefront.source) + " (";
    bool first = true;
    for (size_t j = 0; j < eye.wavefront.coefficients_m.size(); ++j)
      if (eye.wavefront.coefficients_m[j] != 0) {
        line += (first ? "Z" : ", Z") + std::to_string(j) + " " +
                FormatFixed(eye.wavefront.coefficients_m[j] * 1e6, 3) + " um";
        first = false;
      }
    line += " at " + FormatFixed(eye.wavefront.pupil_diameter_m * 1e3, 1) + " mm)";
  }
  if (eye.diffraction == EyeDiffraction::kPupilFunction) {
    line += "; diffraction by the pupil function (wave optics)";
    if (eye.stiles_crawford_rho_per_mm2 > 0)
      line += ", Stiles-Crawford rho " + FormatFixed(eye.stiles_crawford_rho_per_mm2, 3) + " / mm2";
  } else {
    line += eye.diffraction == EyeDiffraction::kPupilMtf ? "; diffraction" : "; no diffraction";
  }
  return line + PoseDescription(eye);
}

}  // namespace layerlab
