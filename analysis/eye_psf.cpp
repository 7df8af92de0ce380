#include "layerlab/analysis/eye_psf.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <cstdio>
#include <filesystem>
#include <numbers>

#include "layerlab/analysis/fourier.h"
#include "layerlab/analysis/svg_plot.h"
#include "layerlab/eye/pupil_function.h"
#include "layerlab/framework/atomic_file.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/png_writer.h"
#include "layerlab/framework/units.h"
#include "layerlab/retina/diffraction.h"
#include "layerlab/retina/eye_optics.h"
#include "layerlab/retina/retina.h"

namespace layerlab {
namespace {

void Check(const EyeModel& eye, const EyePsfOptions& o) {
  if (!(eye.pupil_diameter_m > 0)) throw Error("psf: the eye's pupil is a pinhole (pupil_diameter 0): it has no PSF");
  if (o.vergence_diopters.empty()) throw Error("psf: --vergence: no vergence error given");
  for (double v : o.vergence_diopters)
    if (!std::isfinite(v) || std::abs(v) > 20)
      throw Error("psf: --vergence: " + FormatGeneral(v) + " is not a vergence error within 20 D");
  if (o.frequencies_cpd.empty()) throw Error("psf: --frequencies: no frequency given");
  for (double f : o.frequencies_cpd)
    if (!std::isfinite(f) || !(f >= 0) || f > 1000)
      throw Error("psf: --frequencies: " + FormatGeneral(f) + " is not a frequency in [0, 1000] cpd");
  if (o.psf_size < 3 || o.psf_size > 2049)
    throw Error("psf: --size: " + std::to_string(o.psf_size) + " is not in [3, 2049]");
  if (!(o.psf_spacing_rad >= 0) || !std::isfinite(o.psf_spacing_rad))
    throw Error("psf: --resolution: " + FormatGeneral(o.psf_spacing_rad) + " is not a sample size >= 0");
  const double shortest = *std::min_element(eye.channel_wavelengths_m.begin(), eye.channel_wavelengths_m.end());
  const double limit = shortest / (2 * eye.pupil_diameter_m);
  if (o.psf_spacing_rad > limit)
    throw Error("psf: --resolution: " + FormatGeneral(o.psf_spacing_rad / kRadiansPerDegree * 60) +
                " arcmin would alias the PSF: at most lambda / (2 D) = " +
                FormatGeneral(limit / kRadiansPerDegree * 60) + " arcmin for the " + FormatGeneral(shortest * 1e9) +
                " nm channel and a " + FormatGeneral(eye.pupil_diameter_m * 1e3) + " mm pupil");
}

double Spacing(const EyeModel& eye, const EyePsfOptions& o) {
  if (o.psf_spacing_rad > 0) return o.psf_spacing_rad;
  const double shortest = *std::min_element(eye.channel_wavelengths_m.begin(), eye.channel_wavelengths_m.end());
  return shortest / (4 * eye.pupil_diameter_m);
}

// Re of the OTF the wave-optics retina gives a cosine grating of `cpd` on a plane `vergence` diopters
// nearer than the focus (1 D), per channel: the grating's Fourier coefficient over the middle half of the strip.
std::array<double, 3> RetinaOtf(const EyeOptics& optics, double vergence, double cpd) {
  const RetinaGrid& g = optics.grid();
  const double focus = 1.0, z = 1 / (focus + vergence), f = cpd / kRadiansPerDegree;
  const SceneRadiance grating = [z, f](const PupilPoint& o, double dx, double) {
    const double v = 0.5 + 0.5 * std::cos(2 * std::numbers::pi * f * (o.x_m + dx * z) / z);
    return std::array<double, 3>{v, v, v};
  };
  const Image image = optics.See([&](const RetinaGrid& traced, const std::vector<PupilPoint>& group) {
    return RetinaOfScene(grating, traced, group, {focus, focus, focus});
  });
  const int n = WholeCycleSamples(g.cols / 2, g.resolution_rad / kRadiansPerDegree, cpd), start = (g.cols - n) / 2;
  std::array<double, 3> otf{};
  for (int c = 0; c < 3; ++c) {
    std::complex<double> sum = 0;
    for (int j = start; j < start + n; ++j)
      sum += double(image.at(g.rows / 2, j, c)) * std::polar(1.0, -2 * std::numbers::pi * f * g.angle_x(j));
    otf[c] = (2.0 / n * sum).real() / 0.5;
  }
  return otf;
}

}  // namespace

std::vector<EyeMtfRow> EyeMtfTable(const EyeModel& eye, const EyePsfOptions& o) {
  Check(eye, o);
  const std::vector<PupilPoint> own = PupilSamplesInOwnPlane(eye);
  EyeModel wave_eye = eye;
  wave_eye.diffraction = EyeDiffraction::kPupilFunction;
  wave_eye.pose = {};
  const std::vector<PupilPoint> pupil = PupilSamples(wave_eye);
  const double highest = *std::max_element(o.frequencies_cpd.begin(), o.frequencies_cpd.end());
  const double resolution_deg = std::min(0.01, 1 / (4 * std::max(highest, 1e-9)));
  const EyeOptics optics(
      wave_eye, pupil,
      MakeRetinaGrid(kRadiansPerDegree, 3 * resolution_deg * kRadiansPerDegree, resolution_deg * kRadiansPerDegree),
      RowEdges::kUniform);
  std::vector<EyeMtfRow> rows;
  for (double v : o.vergence_diopters)
    for (double cpd : o.frequencies_cpd) {
      const std::array<double, 3> retina = RetinaOtf(optics, v, cpd);
      for (int c = 0; c < 3; ++c) {
        PupilOptics wave = PupilOpticsOf(eye, eye.channel_wavelengths_m[c]);
        wave.vergence_diopters = v;
        const double f = cpd / kRadiansPerDegree;
        // The rays: a sample at u reads the scene shifted by u V - g(u) (retina/retina.h).
        std::complex<double> rays = 0;
        for (const PupilPoint& u : own) rays += std::polar(1.0, 2 * std::numbers::pi * f * (u.x_m * v - u.slope_x));
        rays /= double(own.size());
        const double mtf = DiffractionOtf(eye.pupil_shape, eye.pupil_diameter_m, eye.channel_wavelengths_m[c], f, 0);
        rows.push_back(
            {c, eye.channel_wavelengths_m[c], v, cpd, PupilOtf(wave, f, 0, 256).real(), retina[c], rays.real() * mtf});
      }
    }
  std::stable_sort(rows.begin(), rows.end(),
                   [](const EyeMtfRow& a, const EyeMtfRow& b) { return a.channel < b.channel; });
  return rows;
}

Image EyePsfImage(const EyeModel& eye, const EyePsfOptions& o, double vergence_diopters) {
  Check(eye, o);
  const int n = o.psf_size;
  Image image{n, n, {"R", "G", "B"}, std::vector<float>(size_t(n) * n * 3)};
  for (int c = 0; c < 3; ++c) {
    PupilOptics optics = PupilOpticsOf(eye, eye.channel_wavelengths_m[c]);
    optics.vergence_diopters = vergence_diopters;
    const PointSpread psf = PupilPointSpread(optics, Spacing(eye, o), n);
    for (size_t k = 0; k < psf.density.size(); ++k) image.pixels[k * 3 + c] = static_cast<float>(psf.density[k]);
  }
  return image;
}

void WriteEyePsf(const EyeModel& eye, const EyePsfOptions& o, const std::string& folder) {
  const std::vector<EyeMtfRow> rows = EyeMtfTable(eye, o);
  std::string csv = "channel,wavelength_nm,vergence_D,frequency_cpd,otf_wave,otf_wave_retina,otf_geometric\n";
  for (const EyeMtfRow& r : rows) {
    char line[192];
    std::snprintf(line, sizeof line, "%s,%.1f,%.4f,%.4f,%.6f,%.6f,%.6f\n",
                  r.channel == 0   ? "R"
                  : r.channel == 1 ? "G"
                                   : "B",
                  r.wavelength_m * 1e9, r.vergence_diopters, r.frequency_cpd, r.wave, r.retina, r.geometric);
    csv += line;
  }
  WriteFileAtomically((std::filesystem::path(folder) / "mtf.csv").string(), csv);
  PlotPanel panel;
  panel.x_label = "frequency (cpd)",
  panel.y_label = "OTF, green (" + FormatFixed(eye.channel_wavelengths_m[1] * 1e9, 0) + " nm)";
  panel.x_min = 0, panel.x_max = *std::max_element(o.frequencies_cpd.begin(), o.frequencies_cpd.end());
  panel.y_min = -0.3, panel.y_max = 1;
  const char* colors[] = {"#1b9e77", "#d95f02", "#7570b3", "#e7298a", "#66a61e", "#e6ab02", "#a6761d", "#666666"};
  for (size_t k = 0; k < o.vergence_diopters.size(); ++k) {
    PlotLine wave{FormatFixed(o.vergence_diopters[k], 2) + " D, wave", colors[k % 8], false, {}, {}};
    PlotLine geometric{FormatFixed(o.vergence_diopters[k], 2) + " D, geometric x MTF", colors[k % 8], true, {}, {}};
    for (const EyeMtfRow& r : rows)
      if (r.channel == 1 && r.vergence_diopters == o.vergence_diopters[k]) {
        wave.x.push_back(r.frequency_cpd), wave.y.push_back(r.wave);
        geometric.x.push_back(r.frequency_cpd), geometric.y.push_back(r.geometric);
      }
    panel.lines.push_back(wave), panel.lines.push_back(geometric);
  }
  WriteFileAtomically((std::filesystem::path(folder) / "mtf.svg").string(),
                      RenderSvg({panel}, 1, "The eye's OTF by its pupil function and by its rays"));
  for (double v : o.vergence_diopters) {
    const Image psf = EyePsfImage(eye, o, v);
    char stem[64];
    std::snprintf(stem, sizeof stem, "psf_%.2fD", v);
    const std::string path = (std::filesystem::path(folder) / stem).string();
    WriteExr(path + ".exr", psf);
    const float peak = *std::max_element(psf.pixels.begin(), psf.pixels.end());
    WriteSrgbPng(path + ".png", psf.width, psf.height, psf.pixels, peak);
  }
}

}  // namespace layerlab
