// The retina's wave optics (retina/eye_optics.h) against the pupil
// function's closed forms: a defocused grating's contrast is Hopkins' OTF (the
// multiplied MTFs are not), in focus it is the diffraction-limited MTF, a
// Zernike defocus is an accommodation, a uniform field keeps its luminance,
// and on a 1 deg field the contrast equals the MTF over the whole field (the
// field padded by the scene itself).
#include <cmath>
#include <complex>
#include <numbers>

#include "layerlab/analysis/fourier.h"
#include "layerlab/framework/units.h"
#include "layerlab/retina/diffraction.h"
#include "layerlab/retina/eye_optics.h"
#include "layerlab/retina/retina.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

constexpr double kPi = std::numbers::pi;

EyeModel RoundEye(double diameter, int samples, EyeDiffraction diffraction) {
  EyeModel eye;
  eye.pupil_shape = PupilShape::kRound;
  eye.pupil_diameter_m = diameter;
  eye.pupil_samples_x = eye.pupil_samples_y = samples;
  eye.channel_wavelengths_m = {555e-9, 555e-9, 555e-9};
  eye.diffraction = diffraction;
  return eye;
}

// A vertical cosine grating of `cpd` on a plane at `diopters` (angles from the pupil's centre).
SceneRadiance Grating(double diopters, double cpd) {
  const double z = 1 / diopters, f = cpd / kRadiansPerDegree;
  return [z, f](const PupilPoint& o, double dx, double) {
    const double v = 0.5 + 0.5 * std::cos(2 * kPi * f * (o.x_m + dx * z) / z);
    return std::array<double, 3>{v, v, v};
  };
}

// The grating's contrast over the middle row's whole cycles (all of the field with `whole`, else its middle half).
double Contrast(const Image& image, const RetinaGrid& g, double cpd, bool whole) {
  const int n = WholeCycleSamples(whole ? g.cols : g.cols / 2, g.resolution_rad / kRadiansPerDegree, cpd);
  const int start = (g.cols - n) / 2;
  std::vector<double> values, degrees;
  for (int j = start; j < start + n; ++j) {
    values.push_back(image.at(g.rows / 2, j, 1));
    degrees.push_back(g.angle_x(j) / kRadiansPerDegree);
  }
  return FourierAmplitude(values, degrees, cpd) / 0.5;
}

Image Seen(const EyeModel& eye, const SceneRadiance& scene, const RetinaGrid& grid, double focus,
           RowEdges rows = RowEdges::kUniform) {
  const std::vector<PupilPoint> pupil = PupilSamples(eye);
  const EyeOptics optics(eye, pupil, grid, rows);
  return optics.See([&](const RetinaGrid& traced, const std::vector<PupilPoint>& group) {
    return RetinaOfScene(scene, traced, group, {focus, focus, focus});
  });
}

TEST(WaveOptics, ADefocusedGratingHasHopkinsContrastNotTheMultipliedMtfs) {
  // 30 cpd, 3 mm, 0.25 D: Hopkins +0.196; geometric blur times the MTF -0.025.
  const RetinaGrid g = MakeRetinaGrid(1 * kRadiansPerDegree, 0.03 * kRadiansPerDegree, 0.01 * kRadiansPerDegree);
  const double hopkins =
      PupilOtf(PupilOptics{PupilShape::kRound, 3e-3, 555e-9, {}, 0.25, 0}, 30 / kRadiansPerDegree, 0, 512).real();
  EXPECT_NEAR(hopkins, 0.196, 0.002);
  const double wave =
      Contrast(Seen(RoundEye(3e-3, 31, EyeDiffraction::kPupilFunction), Grating(1.25, 30), g, 1.0), g, 30, false);
  EXPECT_NEAR(wave, std::abs(hopkins), 0.01);
  const double product =
      Contrast(Seen(RoundEye(3e-3, 31, EyeDiffraction::kPupilMtf), Grating(1.25, 30), g, 1.0), g, 30, false);
  EXPECT_LT(product, 0.06);
}

TEST(WaveOptics, InFocusTheGratingHasTheDiffractionLimitedMtf) {
  const RetinaGrid g = MakeRetinaGrid(1 * kRadiansPerDegree, 0.03 * kRadiansPerDegree, 0.01 * kRadiansPerDegree);
  for (double cpd : {10.0, 30.0}) {
    const double mtf = DiffractionOtf(PupilShape::kRound, 3e-3, 555e-9, cpd / kRadiansPerDegree, 0);
    const double wave =
        Contrast(Seen(RoundEye(3e-3, 15, EyeDiffraction::kPupilFunction), Grating(1.0, cpd), g, 1.0), g, cpd, false);
    EXPECT_NEAR(wave, mtf, 4e-3) << cpd << " cpd";
  }
}

TEST(WaveOptics, AZernikeDefocusIsAnAccommodation) {
  EyeModel aberrated = RoundEye(4e-3, 15, EyeDiffraction::kPupilFunction);
  aberrated.wavefront.pupil_diameter_m = 4e-3;
  aberrated.wavefront.coefficients_m = {0, 0, 0, 0, 0.2e-6};
  const double power = 4 * std::sqrt(3.0) * 0.2e-6 / (2e-3 * 2e-3);  // 0.346 D
  const RetinaGrid g = MakeRetinaGrid(0.6 * kRadiansPerDegree, 0.03 * kRadiansPerDegree, 0.01 * kRadiansPerDegree);
  const Image with = Seen(aberrated, Grating(1.2, 12), g, 1.0);
  const Image shifted = Seen(RoundEye(4e-3, 15, EyeDiffraction::kPupilFunction), Grating(1.2, 12), g, 1.0 + power);
  double worst = 0;
  for (size_t k = 0; k < with.pixels.size(); ++k)
    worst = std::max(worst, double(std::abs(with.pixels[k] - shifted.pixels[k])));
  EXPECT_LT(worst, 2e-3);
}

// Coma along y (Z7) makes the OTF complex: a horizontal grating's phase moves. The wave-optics retina gives
// the pupil function's OTF at (0, f), sign of the phase included (the rows run toward -y).
TEST(WaveOptics, ComaAlongYGivesThePupilFunctionsComplexOtf) {
  EyeModel eye = RoundEye(4e-3, 15, EyeDiffraction::kPupilFunction);
  eye.wavefront.pupil_diameter_m = 4e-3;
  eye.wavefront.coefficients_m = {0, 0, 0, 0, 0, 0, 0, 0.3e-6};
  const double cpd = 12, f = cpd / kRadiansPerDegree;
  const SceneRadiance grating = [f](const PupilPoint& o, double, double dy) {
    const double v = 0.5 + 0.5 * std::cos(2 * kPi * f * (o.y_m + dy));  // at 1 D: (y + dy z) / z
    return std::array<double, 3>{v, v, v};
  };
  const RetinaGrid g = MakeRetinaGrid(0.05 * kRadiansPerDegree, 1 * kRadiansPerDegree, 0.01 * kRadiansPerDegree);
  const Image image = Seen(eye, grating, g, 1.0, RowEdges::kTrace);
  const int n = WholeCycleSamples(g.rows / 2, 0.01, cpd), start = (g.rows - n) / 2;
  std::complex<double> sum = 0;
  for (int i = start; i < start + n; ++i)
    sum += double(image.at(i, g.cols / 2, 1)) * std::polar(1.0, -2 * kPi * f * g.angle_y(i));
  const std::complex<double> measured = 2.0 / n * sum / 0.5;
  PupilOptics optics = PupilOpticsOf(eye, 555e-9);
  const std::complex<double> otf = PupilOtf(optics, 0, f, 256);
  EXPECT_GT(std::abs(otf.imag()), 0.05) << otf;  // the coma moves the grating
  EXPECT_NEAR(measured.real(), otf.real(), 0.01) << measured << " against " << otf;
  EXPECT_NEAR(measured.imag(), otf.imag(), 0.01) << measured << " against " << otf;
}

TEST(WaveOptics, AUniformFieldKeepsItsLuminanceAndASquarePupilGroupsByItsEdges) {
  EyeModel eye = RoundEye(4e-3, 9, EyeDiffraction::kPupilFunction);
  eye.pupil_shape = PupilShape::kSquare;
  const RetinaGrid g = MakeRetinaGrid(2 * kRadiansPerDegree, 1 * kRadiansPerDegree, 0.05 * kRadiansPerDegree);
  const std::vector<PupilPoint> pupil = PupilSamples(eye);
  const EyeOptics optics(eye, pupil, g);
  // The inner 7 x 7 cells are flat; the x edges, the y edges and the corners each share one part.
  EXPECT_EQ(optics.groups(), 4u);
  EXPECT_EQ(optics.transformed_groups(), 3u);
  const SceneRadiance uniform = [](const PupilPoint&, double, double) { return std::array<double, 3>{0.7, 0.7, 0.7}; };
  const Image image = optics.See([&](const RetinaGrid& traced, const std::vector<PupilPoint>& group) {
    return RetinaOfScene(uniform, traced, group, {1.0, 1.0, 1.0});
  });
  for (float v : image.pixels) ASSERT_NEAR(v, 0.7, 1e-5);
}

TEST(EyeOptics, OnAOneDegreeFieldTheWholeFieldsContrastIsTheMtf) {
  const RetinaGrid g = MakeRetinaGrid(1 * kRadiansPerDegree, 0.015 * kRadiansPerDegree, 0.005 * kRadiansPerDegree);
  const EyeModel eye = RoundEye(3e-3, 1, EyeDiffraction::kPupilMtf);
  for (double cpd : {5.0, 10.0}) {
    const double mtf = DiffractionOtf(PupilShape::kRound, 3e-3, 555e-9, cpd / kRadiansPerDegree, 0);
    const double padded = std::abs(Contrast(Seen(eye, Grating(1.0, cpd), g, 1.0), g, cpd, true) - mtf);
    EXPECT_LT(padded, 1e-3) << cpd << " cpd";
    // Extended by its edge values instead, the field's contrast is off by more.
    Image edged = RetinaOfScene(Grating(1.0, cpd), g, PupilSamples(eye), {1.0, 1.0, 1.0});
    ApplyDiffraction(PupilShape::kRound, 3e-3, {555e-9, 555e-9, 555e-9}, g, &edged);
    EXPECT_GT(std::abs(Contrast(edged, g, cpd, true) - mtf), 3 * padded) << cpd << " cpd, padded off by " << padded;
  }
}

}  // namespace
}  // namespace layerlab
