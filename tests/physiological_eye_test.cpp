// The physiological eye's options against independent values: the chromatic
// eye's published spread, Watson and Yellott's pupil worked out by hand,
// Zernike wavefronts against their hand-derived transverse ray aberrations.
#include <cmath>
#include <numbers>

#include "layerlab/analysis/fourier.h"
#include "layerlab/elements/wavefront.h"
#include "layerlab/eye/chromatic_eye.h"
#include "layerlab/eye/eye_description.h"
#include "layerlab/eye/pupil_size.h"
#include "layerlab/framework/units.h"
#include "layerlab/retina/lightfield_radiance.h"
#include "layerlab/retina/retina.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

using nlohmann::json;
using testing::CompileJson;
using testing::ElementNamed;
using testing::ReadExample;

TEST(ChromaticEye, ThibosSpreadsAbout1Point2DioptersFrom450To650Nm) {
  // Rx(0.45 um) = 1.68524 - 0.63346 / 0.23590 = -1.00005 D; Rx(0.65 um) =
  // 1.68524 - 0.63346 / 0.43590 = 0.23202 D: 1.232 D apart (Thibos et al.
  // 1992 report about 1.2 D over the visible), within 0.004 D of zero at 589 nm.
  EXPECT_NEAR(ThibosRefraction(450e-9), -1.000050, 1e-5);
  EXPECT_NEAR(ThibosRefraction(650e-9), 0.232017, 1e-5);
  EXPECT_NEAR(ThibosDefocus(450e-9, 555e-9) - ThibosDefocus(650e-9, 555e-9), 1.232067, 1e-5);
  EXPECT_NEAR(ThibosRefraction(589.3e-9), -0.003086, 1e-5);  // the model eye is emmetropic near 589 nm
  EXPECT_EQ(ThibosDefocus(555e-9, 555e-9), 0.0);
  // Blue is focused nearer than the reference (the eye has more power there), red farther.
  EXPECT_NEAR(ThibosDefocus(465e-9, 555e-9), 0.666552, 1e-5);
  EXPECT_NEAR(ThibosDefocus(612e-9, 555e-9), -0.266191, 1e-5);
}

json PhysiologicalScene(const json& eye_options) {
  json scene = ReadExample("multiplicative_2layer.json");
  for (const auto& [key, value] : eye_options.items()) ElementNamed(scene, "eye")[key] = value;
  return scene;
}

TEST(ChromaticEye, ThibosChannelsFocusAtTheirWavelengths) {
  DisplaySystem s = CompileJson(PhysiologicalScene({{"chromatic_aberration", "thibos"}}));
  std::array<double, 3> focus = ChannelAccommodation(s.eye, 1.0);
  // The default channel wavelengths 612, 549, 465 nm against 555 nm.
  EXPECT_NEAR(focus[0], 1.0 - 0.266191, 1e-5);
  EXPECT_NEAR(focus[1], 1.0 + 0.033291, 1e-5);
  EXPECT_NEAR(focus[2], 1.0 + 0.666552, 1e-5);
  // Stated wavelengths, the reference among them, and the hand-typed defocus on top.
  s = CompileJson(PhysiologicalScene({{"chromatic_aberration", "thibos"},
                                      {"reference_wavelength", "550 nm"},
                                      {"channel_wavelengths", {"650 nm", "550 nm", "450 nm"}},
                                      {"chromatic_defocus", {"0.1 D", "0 D", "0 D"}}}));
  focus = ChannelAccommodation(s.eye, 0.5);
  const double rx550 = 1.68524 - 0.63346 / (0.550 - 0.21410);
  EXPECT_NEAR(focus[0], 0.5 + 0.1 + rx550 - 0.232017, 1e-5);
  EXPECT_EQ(focus[1], 0.5);
  EXPECT_NEAR(focus[2], 0.5 + rx550 + 1.000050, 1e-5);
  // The ideal eye is untouched.
  DisplaySystem ideal = CompileJson(ReadExample("multiplicative_2layer.json"));
  EXPECT_EQ(ChannelAccommodation(ideal.eye, 0.7), (std::array<double, 3>{0.7, 0.7, 0.7}));
  EXPECT_EQ(EyeModelLine(ideal.eye), "ideal eye (geometric optics): 4.00 mm square pupil; no diffraction");
}

// Each channel focuses at the accommodation plus its own hand-typed defocus plus Rx(reference) - Rx(its wavelength),
// for several wavelength sets and all three channels typed apart: no channel reads another's.
TEST(ChromaticEye, EachChannelsFocusIsItsOwnHandTypedAndThibosDefocus) {
  auto rx = [](double nm) { return 1.68524 - 0.63346 / (nm * 1e-3 - 0.21410); };
  const std::array<double, 3> typed = {0.1, -0.2, 0.35};
  struct Wavelengths {
    double reference;
    std::array<double, 3> channels;
  };
  for (const Wavelengths& w :
       {Wavelengths{555, {612, 549, 465}}, Wavelengths{500, {640, 530, 440}}, Wavelengths{600, {700, 580, 410}}})
    for (const bool thibos : {false, true}) {
      json eye = {{"reference_wavelength", std::to_string(w.reference) + " nm"},
                  {"chromatic_defocus", {"0.1 D", "-0.2 D", "0.35 D"}},
                  {"channel_wavelengths", json::array()}};
      for (double nm : w.channels) eye["channel_wavelengths"].push_back(std::to_string(nm) + " nm");
      if (thibos) eye["chromatic_aberration"] = "thibos";
      const DisplaySystem s = CompileJson(PhysiologicalScene(eye));
      for (double accommodation : {0.0, 1.7}) {
        const std::array<double, 3> focus = ChannelAccommodation(s.eye, accommodation);
        for (int c = 0; c < 3; ++c)
          EXPECT_NEAR(focus[c], accommodation + typed[c] + (thibos ? rx(w.reference) - rx(w.channels[c]) : 0), 1e-9)
              << "channel " << c << " at " << w.channels[c] << " nm, reference " << w.reference << " nm"
              << (thibos ? ", thibos" : "");
      }
    }
}

TEST(PupilSize, WatsonYellottAgainstTheEquationByHand) {
  // F = L a M(e); s = (F / 846)^0.41; D_SD = 7.75 - 5.75 s / (s + 2);
  // D = D_SD + (y - 28.58)(0.02132 - 0.009562 D_SD). First row by hand:
  // F = 100 * 400 * 0.1 = 4000, F/846 = 4.72813, s = exp(0.41 ln 4.72813) = 1.89068,
  // 5.75 * 1.89068 / 3.89068 = 2.79424, D = 7.75 - 2.79424 = 4.95577 mm.
  struct Row {
    double luminance, area, age;
    int eyes;
    double mm;
  };
  const Row rows[] = {{100, 400, 28.58, 1, 4.955766}, {100, 400, 28.58, 2, 3.676422}, {1, 900, 45, 2, 5.240087},
                      {10, 100, 60, 1, 5.397962},     {1000, 1000, 20, 2, 2.597547},  {50, 200, 30, 1, 5.697015}};
  for (const Row& r : rows) {
    PupilAdaptation a{r.luminance, r.area, r.age, r.eyes};
    EXPECT_NEAR(WatsonYellottPupilDiameter(a) * 1e3, r.mm, 2e-6) << r.luminance << " cd/m2, " << r.area << " deg2";
  }
  EXPECT_THROW(WatsonYellottPupilDiameter({0, 100, 30, 1}), Error);
  EXPECT_THROW(WatsonYellottPupilDiameter({10, 100, 90, 1}), Error);
}

TEST(PupilSize, AutoPupilFollowsTheDisplaysLuminanceAndField) {
  DisplaySystem ideal = CompileJson(ReadExample("multiplicative_2layer.json"));
  DisplaySystem s = CompileJson(PhysiologicalScene({{"pupil_diameter", "auto"}}));
  double white = 0;
  for (int c = 0; c < 3; ++c) white += kLuminanceWeights[c] * ideal.peak_luminance_cd_m2[c];
  const double area = ideal.fov_x_rad * ideal.fov_y_rad / (kRadiansPerDegree * kRadiansPerDegree);
  EXPECT_NEAR(s.eye.pupil_luminance_used_cd_m2, 0.5 * white, 1e-9);
  EXPECT_NEAR(s.eye.pupil_field_area_used_deg2, area, 1e-9);
  EXPECT_NEAR(s.eye.pupil_diameter_m, WatsonYellottPupilDiameter({0.5 * white, area, 28.58, 1}), 1e-15);
  s = CompileJson(PhysiologicalScene({{"pupil_diameter", "auto"},
                                      {"pupil_luminance", "100 cd/m2"},
                                      {"pupil_field", {"20 deg", "20 deg"}},
                                      {"pupil_eyes", 1}}));
  EXPECT_NEAR(s.eye.pupil_diameter_m, 4.955766e-3, 2e-9);  // the table's first row
  EXPECT_NE(EyeModelLine(s.eye).find("4.96 mm square pupil (auto: Watson & Yellott 2012 at 100.0 cd/m2 over 400 deg2"),
            std::string::npos)
      << EyeModelLine(s.eye);
}

TEST(Zernike, OsaIndicesAndPolynomialsByHand) {
  EXPECT_EQ(ZernikeOrderOf(0).n, 0);
  EXPECT_EQ(ZernikeOrderOf(3).n, 2);
  EXPECT_EQ(ZernikeOrderOf(3).m, -2);
  EXPECT_EQ(ZernikeOrderOf(4).n, 2);
  EXPECT_EQ(ZernikeOrderOf(4).m, 0);
  EXPECT_EQ(ZernikeOrderOf(8).n, 3);
  EXPECT_EQ(ZernikeOrderOf(8).m, 1);
  EXPECT_EQ(ZernikeOrderOf(12).n, 4);
  EXPECT_EQ(ZernikeOrderOf(12).m, 0);
  EXPECT_EQ(ZernikeOrderOf(27).n, 6);
  EXPECT_EQ(ZernikeOrderOf(27).m, 6);
  EXPECT_THROW(ZernikeOrderOf(28), Error);
  const double x = 0.3, y = -0.5, r2 = x * x + y * y, t = std::atan2(y, x);
  EXPECT_NEAR(Zernike(4, x, y), std::sqrt(3.0) * (2 * r2 - 1), 1e-12);
  EXPECT_NEAR(Zernike(3, x, y), std::sqrt(6.0) * 2 * x * y, 1e-12);         // rho^2 sin 2 theta
  EXPECT_NEAR(Zernike(5, x, y), std::sqrt(6.0) * (x * x - y * y), 1e-12);   // rho^2 cos 2 theta
  EXPECT_NEAR(Zernike(7, x, y), std::sqrt(8.0) * (3 * r2 - 2) * y, 1e-12);  // vertical coma
  EXPECT_NEAR(Zernike(8, x, y), std::sqrt(8.0) * (3 * r2 - 2) * x, 1e-12);  // horizontal coma
  EXPECT_NEAR(Zernike(12, x, y), std::sqrt(5.0) * (6 * r2 * r2 - 6 * r2 + 1), 1e-12);
  EXPECT_NEAR(Zernike(9, x, y), std::sqrt(8.0) * std::pow(r2, 1.5) * std::cos(3 * t), 1e-12);
  // Slopes: defocus c sqrt(3) (2 r^2 / R^2 - 1) has d/dx = 4 sqrt(3) c x / R^2.
  Wavefront w;
  w.coefficients_m = {0, 0, 0, 0, 0.5e-6};
  w.pupil_diameter_m = 6e-3;
  WavefrontSlope g = WavefrontSlopeAt(w, 1e-3, -2e-3);
  EXPECT_NEAR(g.x, 4 * std::sqrt(3.0) * 0.5e-6 * 1e-3 / 9e-6, 1e-12);
  EXPECT_NEAR(g.y, 4 * std::sqrt(3.0) * 0.5e-6 * -2e-3 / 9e-6, 1e-12);
}

EyeModel RoundEye(double pupil, int samples) {
  EyeModel eye;
  eye.pupil_diameter_m = pupil;
  eye.pupil_shape = PupilShape::kRound;
  eye.pupil_samples_x = eye.pupil_samples_y = samples;
  return eye;
}

// A scene of pseudo-random values on a plane at `depth` m.
SceneRadiance Pattern(double depth) {
  return [depth](const PupilPoint& u, double dx, double dy) {
    double x = u.x_m + dx * depth, y = u.y_m + dy * depth;
    double v = 0.5 + 0.25 * std::sin(3.1e3 * x + 1.3e3 * y) + 0.2 * std::cos(5.7e3 * y - 0.9e3 * x);
    return Rgb{v, 0.5 * v, 1 - v};
  };
}

TEST(Zernike, PureDefocusIsTheBlurLawAtTheConvertedPower) {
  // c4 = 0.3 um over a 5 mm pupil is D = 16 sqrt(3) 0.3 / 25 = 0.33255 D of
  // excess power: the eye focused at D_a sees as the ideal eye at D_a + D.
  EyeModel eye = RoundEye(4e-3, 15);
  eye.wavefront.coefficients_m = {0, 0, 0, 0, 0.3e-6};
  eye.wavefront.pupil_diameter_m = 5e-3;
  const double power = 16 * std::sqrt(3.0) * 0.3 / 25;
  RetinaGrid retina = MakeRetinaGrid(2 * kRadiansPerDegree, 1 * kRadiansPerDegree, 0.02 * kRadiansPerDegree);
  EyeModel ideal = eye;
  ideal.wavefront = {};
  for (double da : {0.0, 0.8}) {
    Image aberrated = RetinaOfScene(Pattern(0.6), retina, PupilSamples(eye), {da, da, da});
    Image shifted = RetinaOfScene(Pattern(0.6), retina, PupilSamples(ideal), {da + power, da + power, da + power});
    for (size_t k = 0; k < aberrated.pixels.size(); ++k) ASSERT_NEAR(aberrated.pixels[k], shifted.pixels[k], 2e-6);
  }
  // And so a bright point at z = 0.5 m blurs over pupil x |1/z - D_a - D|:
  // its image's extent on a row through the center.
  const double z = 0.5, da = 1.0, radius = 0.6 * 0.005 * kRadiansPerDegree * z;
  SceneRadiance point = [&](const PupilPoint& u, double dx, double dy) {
    double x = u.x_m + dx * z, y = u.y_m + dy * z;
    return x * x + y * y <= radius * radius ? Rgb{1, 1, 1} : Rgb{0, 0, 0};
  };
  EyeModel square = eye;
  square.pupil_shape = PupilShape::kSquare;
  square.pupil_samples_x = square.pupil_samples_y = 41;
  RetinaGrid row = MakeRetinaGrid(1.5 * kRadiansPerDegree, 0.015 * kRadiansPerDegree, 0.005 * kRadiansPerDegree);
  Image image = RetinaOfScene(point, row, PupilSamples(square), {da, da, da});
  double lo = INFINITY, hi = -INFINITY;
  for (int j = 0; j < row.cols; ++j)
    if (image.at(1, j, 0) > 0) lo = std::min(lo, row.angle_x(j)), hi = std::max(hi, row.angle_x(j));
  // The outermost pupil points lie half a cell inside the 4 mm square.
  const double expected = 4e-3 * (40.0 / 41.0) * std::abs(1 / z - da - power);
  EXPECT_NEAR(hi - lo, expected, 0.006 * kRadiansPerDegree) << "blur " << (hi - lo) / kRadiansPerDegree << " deg";
}

// The normalized amplitude at `cpd` of a grating at depth 1/dt over accommodation,
// bars vertical (varying along x) or horizontal.
std::vector<double> GratingCurve(const EyeModel& eye, double dt, double cpd, bool vertical_bars,
                                 const std::vector<double>& accommodation) {
  const double field = 8 * kRadiansPerDegree, resolution = 0.01 * kRadiansPerDegree;
  RetinaGrid retina =
      vertical_bars ? MakeRetinaGrid(field, resolution, resolution) : MakeRetinaGrid(resolution, field, resolution);
  const double z = 1 / dt;
  SceneRadiance grating = [&](const PupilPoint& u, double dx, double dy) {
    const double s = vertical_bars ? u.x_m + dx * z : u.y_m + dy * z;
    double v = 0.5 + 0.5 * std::cos(2 * std::numbers::pi * cpd * std::atan(s / z) / kRadiansPerDegree);
    return Rgb{v, v, v};
  };
  const std::vector<PupilPoint> pupil = PupilSamples(eye);
  const int n = vertical_bars ? retina.cols : retina.rows;
  const int used = WholeCycleSamples(n, 0.01, cpd), start = (n - used) / 2;
  std::vector<double> curve;
  for (double da : accommodation) {
    Image image = RetinaOfScene(grating, retina, pupil, {da, da, da});
    std::vector<double> values, degrees;
    for (int k = start; k < start + used; ++k) {
      values.push_back(vertical_bars ? image.at(0, k, 0) : image.at(k, 0, 0));
      degrees.push_back((vertical_bars ? retina.angle_x(k) : retina.angle_y(k)) / kRadiansPerDegree);
    }
    curve.push_back(FourierAmplitude(values, degrees, cpd) / 0.5);
  }
  return curve;
}

std::vector<double> Range(double lo, double hi, double step) {
  std::vector<double> x;
  for (int k = 0; lo + k * step <= hi + 1e-9; ++k) x.push_back(lo + k * step);
  return x;
}

TEST(Zernike, AstigmatismFocusesVerticalAndHorizontalBarsAtTheTwoFocalLines) {
  // c5 sqrt(6) (x^2 - y^2) / R^2: the power along x is 2 sqrt(6) c5 / R^2 =
  // 8 sqrt(6) c5 / p^2 = 8 * 2.44949 * 0.2 / 16 = 0.24495 D, along y its
  // negative. Vertical bars (blurred along x) are sharp where D_a + 0.245 = D_t,
  // horizontal bars where D_a - 0.245 = D_t.
  EyeModel eye = RoundEye(4e-3, 21);
  eye.pupil_shape = PupilShape::kSquare;  // separable: each focal line is a pure defocus of its bars
  eye.wavefront.coefficients_m = {0, 0, 0, 0, 0, 0.2e-6};
  eye.wavefront.pupil_diameter_m = 4e-3;
  const double dt = 1.0, line = 8 * std::sqrt(6.0) * 0.2 / 16;
  const std::vector<double> a = Range(0.5, 1.5, 0.025);
  Peak vertical = FindPeak(a, GratingCurve(eye, dt, 2, true, a));
  Peak horizontal = FindPeak(a, GratingCurve(eye, dt, 2, false, a));
  EXPECT_NEAR(vertical.at_parabola, dt - line, 0.005);
  EXPECT_NEAR(horizontal.at_parabola, dt + line, 0.005);
  EXPECT_GT(vertical.value, 0.99);  // a focal line is in focus for bars across it
  // At the other focal line vertical bars are blurred by 2 x 0.245 D over the
  // square's 4 mm: a box of w = 1.96 mrad = 0.1123 deg, whose transfer at 2 cpd
  // is sinc(2 w) = 0.9195 (21 points across a box stand for it to 0.005).
  const double w = 4e-3 * 2 * line / kRadiansPerDegree, x = std::numbers::pi * 2 * w;
  EXPECT_NEAR(GratingCurve(eye, dt, 2, true, {dt + line})[0], std::sin(x) / x, 0.005);
  EXPECT_NEAR(GratingCurve(eye, dt, 2, false, {dt - line})[0], std::sin(x) / x, 0.005);
}

TEST(Zernike, SphericalAberrationMovesBestFocusAndLowersPeakContrast) {
  // W = c sqrt(5) (6 rho^4 - 6 rho^2 + 1). At low frequency the best focus
  // is the least variance of the transverse aberration along x; over a round
  // pupil, W = a rho^4 + b rho^2 has it at b = -4a/3 (d/db of
  // int (4a rho^3 + 2b rho)^2 rho^3 drho = 0). Zernike's own balance is
  // b = -a, so the eye must add -2 sqrt(5) c rho^2 of defocus: accommodation
  // D_t - 4 sqrt(5) c / R^2 = D_t - 16 sqrt(5) c / p^2, for c = 0.2 um and
  // p = 6 mm 0.19876 D nearer the far side.
  EyeModel eye = RoundEye(6e-3, 61);
  eye.wavefront.coefficients_m.assign(13, 0.0);
  eye.wavefront.coefficients_m[12] = 0.2e-6;
  eye.wavefront.pupil_diameter_m = 6e-3;
  EyeModel ideal = RoundEye(6e-3, 61);
  const double dt = 1.2, shift = -16 * std::sqrt(5.0) * 0.2 / 36;
  const std::vector<double> a = Range(0.8, 1.4, 0.02);
  Peak aberrated = FindPeak(a, GratingCurve(eye, dt, 2, true, a));
  Peak perfect = FindPeak(a, GratingCurve(ideal, dt, 2, true, a));
  EXPECT_NEAR(perfect.at_parabola, dt, 0.002);
  // 61 x 61 points stand for the disk's integral; they put the least variance 0.003 D farther.
  EXPECT_NEAR(aberrated.at_parabola, dt + shift, 0.01);
  EXPECT_NEAR(perfect.value, 1.0, 1e-3);
  EXPECT_LT(aberrated.value, 0.97);  // 0.954 for these points by direct summation of exp(2 pi i f dx)
  EXPECT_GT(aberrated.value, 0.94);
}

TEST(Zernike, WavefrontBeyondItsMeasurementPupilIsWarnedAbout) {
  DisplaySystem s = CompileJson(PhysiologicalScene({{"zernike", "salmon_van_de_pol_2006"}}));
  EXPECT_EQ(s.eye.wavefront.coefficients_m.at(12), 0.13e-6);
  EXPECT_EQ(s.eye.wavefront.pupil_diameter_m, 6e-3);
  bool warned = false;
  for (const std::string& w : s.warnings) warned = warned || w.find("extrapolated") != std::string::npos;
  EXPECT_FALSE(warned);  // a 4 mm square reaches 5.66 mm
  s = CompileJson(PhysiologicalScene({{"zernike", {{"12", "0.1 um"}}}, {"zernike_pupil", "5 mm"}}));
  for (const std::string& w : s.warnings) warned = warned || w.find("extrapolated") != std::string::npos;
  EXPECT_TRUE(warned);
}

}  // namespace
}  // namespace layerlab
