// eye: the viewer, where every optical path starts.
//
// | key                 | type               | default          | meaning                                  |
// |---------------------|--------------------|------------------|------------------------------------------|
// | pupil_diameter      | length, or auto    | 4 mm             | side of a square / diameter of a round pupil; 0 = pinhole; auto: from the luminance at the eye and the field size by the unified formula of Watson and Yellott (2012, J. Vision 12(10):12) |
// | pupil_shape         | square, round      | square           | the paper uses a square pupil            |
// | pupil_samples       | [x, y] integers    | [9, 9]           | pupil points for retinal images          |
// | pupil_sampling      | grid, jittered, poisson | grid        | how those points are placed              |
// | pupil_seed          | integer            | 1                | for jittered and poisson sampling        |
// | eye_relief          | length             | 1 cm             | pupil plane to main lens                 |
// | accommodation_range | [depth, depth]     | ["0 D", "2.6 D"] | far and near point: a layer outside gets a warning; swept by focal stacks and contrast curves |
// | chromatic_defocus   | [r, g, b] optical powers | [0, 0, 0]  | defocus added per channel (longitudinal chromatic aberration) |
// | eyebox              | [length, length]   | [6 mm, 6 mm]     | width, height the views cover            |
// | views               | [x, y] integers    | [13, 13]         | views of target light fields             |
// | chromatic_aberration | none, thibos      | none             | thibos: each channel's defocus from its wavelength by the chromatic eye of Thibos et al. (1992, Appl. Opt. 31:3594), Rx = 1.68524 - 0.63346 / (lambda_um - 0.21410) D, relative to reference_wavelength; added to chromatic_defocus |
// | reference_wavelength | length            | 555 nm           | the wavelength in focus at the accommodation (thibos) |
// | channel_wavelengths | [r, g, b] lengths  | [612, 549, 465] nm | the channels' dominant wavelengths, for thibos, diffraction and real lenses (the spectral tables are read at the defaults) |
// | pupil_luminance     | luminance          | half the display's peak white | pupil_diameter "auto": the luminance at the eye |
// | pupil_field         | [angle, angle]     | the display's field of view | pupil_diameter "auto": width, height of the adapting field (its area counts) |
// | pupil_age           | number, years      | 28.58            | pupil_diameter "auto": the observer's age, 20 to 83 (28.58, the formula's reference age, has no age term) |
// | pupil_eyes          | 1 or 2             | 1                | pupil_diameter "auto": eyes that see the field (1 attenuates the flux ten times) |
// | zernike             | {"j": length}, or a population name | none | wavefront aberration, OSA/ANSI single index j 0 to 27 to coefficient ("0.1 um"); or salmon_van_de_pol_2006: the mean spherical aberration Z12 = 0.13 um at 6 mm of 2560 normal eyes (Salmon and van de Pol 2006, J. Cataract Refract. Surg. 32:2064); each pupil ray deviated by the wavefront's slope |
// | zernike_pupil       | length             | required with coefficients | the pupil diameter the coefficients were measured at (the wavefront is evaluated at r over its radius) |
// | diffraction         | false, true, mtf, wave | false        | true or mtf: each channel's retinal image times the diffraction-limited MTF at its wavelength (round: Airy; square: sinc squared); wave: the image from the generalized pupil function (aperture, Stiles-Crawford, wavefront) and the pupil-sampled views (docs/eye-model.md) |
// | stiles_crawford     | boolean or number  | false            | with diffraction wave: the pupil's amplitude 10^(-rho r^2 / 2), r in mm; true is rho = 0.05 / mm^2 (Applegate & Lakshminarayanan 1993), a number is rho |
// | pupil_offset        | [length, length]   | [0 mm, 0 mm]     | the eye's move across the eye plane (x right, y up): the wearer's fit, a point of an eyebox map; within 5 cm |
// | gaze                | [angle, angle]     | [0 deg, 0 deg]   | where the eye looks, Fick angles: right, then up, within 50 deg; the pupil turns with it about the centre of rotation (elements/eye_pose.h) |
// | rotation_radius     | length             | 10 mm            | pupil centre to the eye's centre of rotation, 0 to 3 cm |
// | binocular           | {"side", "ipd", "display", "fixation"} | none | this is one of two eyes: side left or right, ipd (63 mm), display shared (a direct-view display on the midline: the eye sits ipd/2 off its axis) or own (one display per eye, on its axis), fixation [x, y, z] lengths from the midpoint between the pupils; the eye turns to it (its pose follows; not with pupil_offset or gaze) |
// | next                | element name       | required         | the main lens                            |
#include <algorithm>
#include <cctype>
#include <cmath>
#include <functional>
#include <numbers>
#include <optional>
#include <string>

#include "layerlab/elements/element.h"
#include "layerlab/elements/registry.h"
#include "layerlab/framework/units.h"

namespace layerlab {
namespace {

// Thibos's formula and the channels' spectra hold over the visible.
void RequireVisible(const Params& p, const std::string& key, double wavelength) {
  if (!(wavelength >= 380e-9 && wavelength <= 780e-9))
    p.fail(key, "a wavelength must lie in 380 to 780 nm, got " + FormatFixed(wavelength * 1e9, 1) + " nm");
}

// An optional [R, G, B] of quantities, each passed to `check`; `values` keeps its defaults without the key.
void ReadPerChannel(Params& p, const std::string& key, Dimension d, const std::string& expected,
                    const std::function<void(const Params&, const std::string&, double)>& check,
                    std::array<double, 3>* values) {
  p.mark_read(key);
  if (!p.has(key)) return;
  const nlohmann::json& v = p.raw(key);
  if (!v.is_array() || v.size() != 3) p.fail(key, expected);
  Params rgb(nlohmann::json{{"0", v[0]}, {"1", v[1]}, {"2", v[2]}}, p.where(key));
  for (int c = 0; c < 3; ++c) {
    (*values)[c] = rgb.quantity(std::to_string(c), d);
    check(rgb, std::to_string(c), (*values)[c]);
  }
}

PupilFromLuminance ReadPupilFromLuminance(Params& p) {
  PupilFromLuminance a;
  if (double l = p.quantity("pupil_luminance", Dimension::kLuminance, 0.0); p.has("pupil_luminance")) {
    p.require_range("pupil_luminance", l, 0.0, 1e7, true, false);
    a.luminance_cd_m2 = l;
  }
  auto field = p.quantity_pair("pupil_field", Dimension::kAngle, {0.0, 0.0});
  if (p.has("pupil_field")) {
    p.require_range("pupil_field", std::min(field[0], field[1]), 0.0, std::numbers::pi, true, false);
    p.require_range("pupil_field", std::max(field[0], field[1]), 0.0, std::numbers::pi, true, false);
    a.field_rad = field;
  }
  a.age_years = p.quantity("pupil_age", Dimension::kFraction, a.age_years);
  p.require_range("pupil_age", a.age_years, 20.0, 83.0, false, false);
  a.eyes = static_cast<int>(p.integer("pupil_eyes", 1, 2, a.eyes));
  return a;
}

void ReadPhysiologicalOptics(Params& p, EyeModel& m) {
  m.chromatic_aberration = p.choice("chromatic_aberration", {"none", "thibos"}, "none") == "thibos"
                               ? ChromaticAberration::kThibos
                               : ChromaticAberration::kNone;
  m.reference_wavelength_m = p.quantity("reference_wavelength", Dimension::kLength, m.reference_wavelength_m);
  RequireVisible(p, "reference_wavelength", m.reference_wavelength_m);
  ReadPerChannel(p, "channel_wavelengths", Dimension::kLength, "expected three wavelengths [R, G, B]", RequireVisible,
                 &m.channel_wavelengths_m);
  p.mark_read("zernike");
  const double measured = p.quantity("zernike_pupil", Dimension::kLength, 0.0);
  if (p.has("zernike")) {
    const nlohmann::json& z = p.raw("zernike");
    if (z.is_string()) {
      const Wavefront* population = PopulationWavefront(z.get<std::string>());
      if (!population) {
        std::string names;
        for (const std::string& n : PopulationWavefrontNames()) names += (names.empty() ? "" : ", ") + n;
        p.fail("zernike", "unknown population \"" + z.get<std::string>() + "\"; known: " + names +
                              " (or give {\"j\": coefficient} with zernike_pupil)");
      }
      if (p.has("zernike_pupil")) p.fail("zernike_pupil", "a population's coefficients carry their own pupil");
      m.wavefront = *population;
    } else if (z.is_object()) {
      if (!p.has("zernike_pupil"))
        p.fail("zernike", "coefficients need zernike_pupil, the pupil diameter they were measured at");
      p.require_range("zernike_pupil", measured, 0.0, 0.02, true, false);
      Params terms(z, p.where("zernike"));
      m.wavefront.pupil_diameter_m = measured;
      for (const auto& [key, value] : z.items()) {
        const bool digits = !key.empty() && key.size() <= 2 &&
                            std::all_of(key.begin(), key.end(), [](char ch) { return ch >= '0' && ch <= '9'; });
        const int j = digits ? std::stoi(key) : -1;
        if (j < 0 || j > kMaxZernikeIndex)
          terms.fail(key, "not an OSA/ANSI Zernike index: give j from 0 to " + std::to_string(kMaxZernikeIndex));
        const double c = terms.quantity(key, Dimension::kLength);
        if (!(std::abs(c) <= 50e-6))
          terms.fail(key, "a coefficient must lie within 50 um of 0, got " + FormatFixed(c * 1e6, 3) +
                              " um (a bare number is meters: give \"0.1 um\")");
        if (m.wavefront.coefficients_m.size() <= size_t(j)) m.wavefront.coefficients_m.resize(j + 1, 0.0);
        m.wavefront.coefficients_m[j] = c;
      }
    } else {
      p.fail("zernike", "expected {\"j\": coefficient} or a population name, got " + z.dump());
    }
  } else if (p.has("zernike_pupil")) {
    p.fail("zernike_pupil", "only with zernike coefficients");
  }
  p.mark_read("diffraction");
  if (p.has("diffraction")) {
    const nlohmann::json& d = p.raw("diffraction");
    if (d.is_boolean())
      m.diffraction = d.get<bool>() ? EyeDiffraction::kPupilMtf : EyeDiffraction::kNone;
    else if (d.is_string() && d.get<std::string>() == "mtf")
      m.diffraction = EyeDiffraction::kPupilMtf;
    else if (d.is_string() && d.get<std::string>() == "wave")
      m.diffraction = EyeDiffraction::kPupilFunction;
    else
      p.fail("diffraction", "expected false, true (the same as \"mtf\") or \"wave\", got " + d.dump());
  }
  if (m.diffraction != EyeDiffraction::kNone && !m.pupil_auto && m.pupil_diameter_m == 0)
    p.fail("diffraction", "a pinhole pupil (pupil_diameter 0) has no diffraction-limited image");
  p.mark_read("stiles_crawford");
  if (p.has("stiles_crawford")) {
    const nlohmann::json& sc = p.raw("stiles_crawford");
    if (sc.is_boolean())
      m.stiles_crawford_rho_per_mm2 = sc.get<bool>() ? kStilesCrawfordRhoPerMm2 : 0.0;
    else if (sc.is_number() && std::isfinite(sc.get<double>()) && sc.get<double>() >= 0 && sc.get<double>() <= 1)
      m.stiles_crawford_rho_per_mm2 = sc.get<double>();
    else
      p.fail("stiles_crawford", "expected true, false or rho per mm^2 in [0, 1], got " + sc.dump());
    if (m.stiles_crawford_rho_per_mm2 > 0 && m.diffraction != EyeDiffraction::kPupilFunction)
      p.fail("stiles_crawford",
             "the Stiles-Crawford apodization is part of the pupil function: set diffraction \"wave\"");
  }
}

// Where the eye sits and looks (elements/eye_pose.h); compile checks the
// pose against the eyebox and the display's field (systems/eye_pose_limits.h).
void ReadPose(Params& p, EyePose& pose) {
  pose.pupil_offset_m = p.quantity_pair("pupil_offset", Dimension::kLength, pose.pupil_offset_m);
  for (double v : pose.pupil_offset_m)
    p.require_range("pupil_offset", v, -kMaxPupilOffset, kMaxPupilOffset, false, false);
  pose.gaze_rad = p.quantity_pair("gaze", Dimension::kAngle, pose.gaze_rad);
  for (double v : pose.gaze_rad) p.require_range("gaze", v, -kMaxGaze, kMaxGaze, false, false);
  pose.rotation_radius_m = p.quantity("rotation_radius", Dimension::kLength, pose.rotation_radius_m);
  p.require_range("rotation_radius", pose.rotation_radius_m, 0.0, kMaxRotationRadius, false, false);
}

// One of two eyes turned to a fixated point (elements/eye_pose.h): its pose follows.
std::optional<Binocular> ReadBinocular(Params& p, EyePose& pose) {
  if (!p.has("binocular")) return std::nullopt;
  for (const char* key : {"pupil_offset", "gaze"})
    if (p.has(key)) p.fail(key, "not with \"binocular\": the pair's geometry places and turns the eye");
  Params b = p.object("binocular");
  Binocular pair;
  if (!b.has("side")) b.fail("side", "say which eye this is: \"left\" or \"right\"");
  pair.side = b.choice("side", {"left", "right"}, "left") == "left" ? -1 : 1;
  pair.ipd_m = b.quantity("ipd", Dimension::kLength, pair.ipd_m);
  b.require_range("ipd", pair.ipd_m, 0.0, 0.1, true, false);
  pair.shared_display = b.choice("display", {"shared", "own"}, "shared") == "shared";
  if (!b.has("fixation")) b.fail("fixation", "give the fixated point [x, y, z] (z toward the display)");
  const nlohmann::json& f = b.raw("fixation");
  if (!f.is_array() || f.size() != 3) b.fail("fixation", "expected a point [x, y, z] of lengths, got " + f.dump());
  Params xyz(nlohmann::json{{"x", f[0]}, {"y", f[1]}, {"z", f[2]}}, b.where("fixation"));
  pair.fixation_m = {xyz.quantity("x", Dimension::kLength), xyz.quantity("y", Dimension::kLength),
                     xyz.quantity("z", Dimension::kLength)};
  xyz.require_range("x", pair.fixation_m[0], -100.0, 100.0, false, false);
  xyz.require_range("y", pair.fixation_m[1], -100.0, 100.0, false, false);
  xyz.require_range("z", pair.fixation_m[2], 0.0, 1000.0, true, false);
  b.check_all_read();
  pose = FixatingPose(pair, pose.rotation_radius_m);
  for (double v : pose.gaze_rad)
    if (std::abs(v) > kMaxGaze)
      b.fail("fixation",
             "the eye would turn " + FormatFixed(std::abs(v) * kDegreesPerRadian, 1) + " deg to it, beyond 50 deg");
  return pair;
}

std::unique_ptr<Element> MakeEye(Params& p) {
  EyeModel m;
  const bool word = p.has("pupil_diameter") && p.raw("pupil_diameter").is_string() &&
                    std::isalpha(static_cast<unsigned char>(p.raw("pupil_diameter").get<std::string>().c_str()[0]));
  if (word && p.raw("pupil_diameter") != "auto")
    p.fail("pupil_diameter", "expected a length (\"4 mm\") or \"auto\", got " + p.raw("pupil_diameter").dump());
  if (word) {
    m.pupil_auto = ReadPupilFromLuminance(p);
  } else {
    m.pupil_diameter_m = p.quantity("pupil_diameter", Dimension::kLength, m.pupil_diameter_m);
    p.require_range("pupil_diameter", m.pupil_diameter_m, 0.0, 0.02, false, false);
    for (const char* key : {"pupil_luminance", "pupil_field", "pupil_age", "pupil_eyes"})
      if (p.has(key)) p.fail(key, "only with \"pupil_diameter\": \"auto\"");
    ReadPupilFromLuminance(p);  // the keys' defaults, for the key recorder
  }
  m.pupil_shape =
      p.choice("pupil_shape", {"square", "round"}, "square") == "square" ? PupilShape::kSquare : PupilShape::kRound;
  if (p.has("pupil_samples")) {
    auto n = p.integer_pair("pupil_samples", 1, 1024);
    m.pupil_samples_x = static_cast<int>(n[0]);
    m.pupil_samples_y = static_cast<int>(n[1]);
  }
  std::string sampling = p.choice("pupil_sampling", {"grid", "jittered", "poisson"}, "grid");
  m.pupil_sampling = sampling == "grid"       ? PupilSampling::kGrid
                     : sampling == "jittered" ? PupilSampling::kJittered
                                              : PupilSampling::kPoisson;
  m.pupil_seed = static_cast<uint64_t>(p.integer("pupil_seed", 0, INT64_MAX, 1));
  m.eye_relief_m = p.quantity("eye_relief", Dimension::kLength, m.eye_relief_m);
  p.require_range("eye_relief", m.eye_relief_m, 0.0, 1.0, true, false);

  p.mark_read("accommodation_range");
  if (p.has("accommodation_range")) {
    const nlohmann::json& range = p.raw("accommodation_range");
    if (!range.is_array() || range.size() != 2)
      p.fail("accommodation_range", "expected two depths [\"0 D\", \"2.6 D\"], got " + range.dump());
    Params ends(nlohmann::json{{"0", range[0]}, {"1", range[1]}}, p.where("accommodation_range"));
    m.accommodation_min_diopters = ends.optional_depth("0")->diopters;
    m.accommodation_max_diopters = ends.optional_depth("1")->diopters;
    if (!(m.accommodation_min_diopters < m.accommodation_max_diopters))
      p.fail("accommodation_range", "the range is inverted or empty: " + FormatFixed(m.accommodation_min_diopters, 3) +
                                        " D is not below " + FormatFixed(m.accommodation_max_diopters, 3) +
                                        " D (give [far, near] in diopters, far first)");
  }
  ReadPerChannel(
      p, "chromatic_defocus", Dimension::kOpticalPower, "expected three powers [R, G, B] in D",
      [](const Params& rgb, const std::string& key, double v) { rgb.require_range(key, v, -5.0, 5.0, false, false); },
      &m.chromatic_defocus_diopters);
  ReadPhysiologicalOptics(p, m);
  auto eyebox = p.quantity_pair("eyebox", Dimension::kLength, {m.eyebox_width_m, m.eyebox_height_m});
  m.eyebox_width_m = eyebox[0];
  m.eyebox_height_m = eyebox[1];
  p.require_range("eyebox", std::min(eyebox[0], eyebox[1]), 0.0, 0.1, true, false);
  p.require_range("eyebox", std::max(eyebox[0], eyebox[1]), 0.0, 0.1, true, false);
  ReadPose(p, m.pose);
  m.binocular = ReadBinocular(p, m.pose);
  if (p.has("views")) {
    auto n = p.integer_pair("views", 1, 256);
    m.views_x = static_cast<int>(n[0]);
    m.views_y = static_cast<int>(n[1]);
  }
  return std::make_unique<EyeElement>(m);
}

}  // namespace

ElementType EyeType() { return {"eye", ElementKind::kEye, "the viewer: pupil, eye relief, views", MakeEye}; }

}  // namespace layerlab
