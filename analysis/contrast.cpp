#include "analysis/contrast.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <numbers>

#include "analysis/svg_plot.h"
#include "framework/error.h"
#include "solvers/solve_config.h"
#include "systems/compile.h"
#include "systems/display_model.h"
#include "systems/retina.h"

namespace layerlab {
namespace {

constexpr double kDeg = std::numbers::pi / 180;

double Seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

// The light field of the textured plane at D_t, which is also the origin plane:
// every view sees the texture at the pixel's own origin-plane position.
LightField PlaneTarget(const LightFieldGeometry& g, const PlaneTexture& texture) {
  LightField lf(g);
  for (int i = 0; i < g.rows; ++i)
    for (int j = 0; j < g.cols; ++j) {
      Rgb value = texture(g.pixel_x(j), g.pixel_y(i));
      for (size_t v = 0; v < g.view_count(); ++v)
        for (int c = 0; c < 3; ++c) lf.view(v)[(size_t(i) * g.cols + j) * 3 + c] = static_cast<float>(value[c]);
    }
  return lf;
}

// Luminance along the central retinal row, for the Fourier amplitude.
std::vector<double> CentralRow(const Image& image) {
  std::vector<double> row(image.width);
  int i = image.height / 2;
  for (int j = 0; j < image.width; ++j)
    for (int c = 0; c < 3; ++c) row[j] += kLuminanceWeights[c] * image.at(i, j, c);
  return row;
}

double Interpolate(const std::vector<double>& x, const std::vector<double>& y, double at) {
  for (size_t k = 1; k < x.size(); ++k)
    if (at <= x[k] + 1e-12) {
      double f = (at - x[k - 1]) / (x[k] - x[k - 1]);
      return y[k - 1] + std::clamp(f, 0.0, 1.0) * (y[k] - y[k - 1]);
    }
  return y.back();
}

}  // namespace

PlaneTextureFactory CosineGrating(double mean, double contrast) {
  return [mean, contrast](double depth, double cpd) -> PlaneTexture {
    double k = cpd / (depth * kDeg);  // cycles per meter on the plane
    return [=](double s, double) {
      double v = mean * (1 + contrast * std::cos(2 * std::numbers::pi * k * s));
      return Rgb{v, v, v};
    };
  };
}

ContrastDisplay LoadContrastDisplay(const std::string& scene_file) {
  Scene scene = LoadScene(scene_file);
  ContrastDisplay d;
  d.system = Compile(scene);
  d.name = std::filesystem::path(scene_file).stem().string();
  if (scene.document.contains("solve")) {
    SolveConfig config = ReadSolveConfig(scene, d.system);
    d.solver = config.solver;
    d.options = config.options;
    d.options_given = true;
  }
  return d;
}

std::vector<ContrastCurve> RunContrast(const std::vector<ContrastDisplay>& displays, const ContrastOptions& o) {
  if (displays.empty()) throw Error("contrast: no display given");
  if (!(o.accommodation_step > 0) || !(o.accommodation_max > o.accommodation_min))
    throw Error("contrast: the accommodation range must be increasing with a positive step");
  std::vector<double> accommodation;
  for (int k = 0;; ++k) {
    double a = o.accommodation_min + k * o.accommodation_step;
    if (a > o.accommodation_max + 1e-9) break;
    accommodation.push_back(a);
  }
  const EyeModel& eye = displays.front().system.eye;
  std::vector<PupilPoint> pupil = PupilSamples(eye);
  RetinaGrid retina = MakeRetinaGrid(o.retina_field * kDeg, 3 * o.retina_resolution * kDeg, o.retina_resolution * kDeg);
  std::vector<double> degrees(retina.cols);
  for (int j = 0; j < retina.cols; ++j) degrees[j] = retina.angle_x(j) / kDeg;

  auto amplitude = [&](const Image& image, double f) {
    std::vector<double> row = CentralRow(image);
    int n = WholeCycleSamples(retina.cols, o.retina_resolution, f);
    int start = (retina.cols - n) / 2;
    return FourierAmplitude(std::vector<double>(row.begin() + start, row.begin() + start + n),
                            std::vector<double>(degrees.begin() + start, degrees.begin() + start + n), f);
  };

  std::vector<ContrastCurve> curves;
  for (double f : o.frequencies)
    for (double dt : o.target_diopters) {
      PlaneTexture texture = o.texture(1 / dt, f);
      char label[96];
      std::snprintf(label, sizeof label, "target %.2f D, %.1f cpd", dt, f);
      // Natural viewing of the plane, and its amplitude focused on it.
      auto start = std::chrono::steady_clock::now();
      SceneRadiance plane = [&](const PupilPoint& u, double dx, double dy) {
        return texture(u.x + dx / dt, u.y + dy / dt);
      };
      ContrastCurve natural{"natural", dt, f, accommodation, {}, {}, 0, 0, 0, 0, "-"};
      double reference = amplitude(RetinaOfScene(plane, retina, pupil, ChannelAccommodation(eye, dt)), f);
      if (!(reference > 0)) throw Error(std::string("contrast: the target has no component at ") + label);
      for (double a : accommodation)
        natural.contrast.push_back(amplitude(RetinaOfScene(plane, retina, pupil, ChannelAccommodation(eye, a)), f) / reference);
      natural.sweep_seconds = Seconds(start);
      curves.push_back(natural);

      for (const ContrastDisplay& d : displays) {
        if (o.progress) o.progress(d.name + ": " + label);
        LightFieldGeometry g = DisplayLightFieldGeometry(d.system, dt);
        double row_height = g.window_height / g.rows;
        g.rows = std::min(g.rows, o.strip_rows);
        g.window_height = g.rows * row_height;
        g.window_top = g.window_height / 2;
        DisplayModel model(d.system, g);
        LightField target = PlaneTarget(g, texture);
        ContrastCurve curve{d.name, dt, f, accommodation, {}, {}, 0, 0, 0, 0, ""};
        curve.solver = d.solver.empty() ? DefaultSolverFor(d.system) : d.solver;
        SolverOptions options = d.options_given ? d.options : SolverRegistry::Builtins().find(curve.solver)->defaults;
        Patterns t;
        start = std::chrono::steady_clock::now();
        SolverReport report = SolverRegistry::Builtins().create(curve.solver)->Solve(model, target, options, &t);
        if (!report.IsSolutionUsable()) throw Error("contrast: " + d.name + ": " + report.message);
        curve.solve_seconds = Seconds(start);
        curve.psnr_db = report.final_psnr_db;
        start = std::chrono::steady_clock::now();
        for (double a : accommodation)
          curve.contrast.push_back(amplitude(RetinaOfDisplay(model, t, retina, pupil, ChannelAccommodation(eye, a)), f) /
                                   reference);
        curve.sweep_seconds = Seconds(start);
        curves.push_back(curve);
      }
    }
  for (ContrastCurve& c : curves) {
    c.peak = FindPeak(c.accommodation, c.contrast);
    c.at_target = Interpolate(c.accommodation, c.contrast, c.target_diopters);
  }
  return curves;
}

std::string ContrastCsv(const std::vector<ContrastCurve>& curves) {
  std::string csv = "display,target_D,frequency_cpd,accommodation_D,normalized_contrast\n";
  char line[256];
  for (const ContrastCurve& c : curves)
    for (size_t k = 0; k < c.accommodation.size(); ++k) {
      std::snprintf(line, sizeof line, "%s,%.4f,%.4f,%.4f,%.6f\n", c.display.c_str(), c.target_diopters, c.frequency,
                    c.accommodation[k], c.contrast[k]);
      csv += line;
    }
  return csv;
}

std::string PeakTable(const std::vector<ContrastCurve>& curves) {
  std::string out = "display                  target (D)  f (cpd)  peak (D)  parabola (D)  peak contrast  at target  solver                 PSNR (dB)  solve (s)  sweep (s)\n";
  char line[320];
  for (const ContrastCurve& c : curves) {
    std::snprintf(line, sizeof line, "%-24s %10.2f %8.1f %9.2f %13.3f %14.3f %10.3f  %-22s %9.2f %10.3f %10.3f\n",
                  c.display.c_str(), c.target_diopters, c.frequency, c.peak.at_grid, c.peak.at_parabola, c.peak.value,
                  c.at_target, c.solver.c_str(), c.psnr_db, c.solve_seconds, c.sweep_seconds);
    out += line;
  }
  return out;
}

std::string ContrastSvg(const std::vector<ContrastCurve>& curves) {
  static const char* kColors[] = {"#d62728", "#2ca02c", "#1f77b4", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2"};
  std::vector<double> frequencies, depths;
  std::vector<std::string> displays;
  for (const ContrastCurve& c : curves) {
    if (std::find(frequencies.begin(), frequencies.end(), c.frequency) == frequencies.end()) frequencies.push_back(c.frequency);
    if (std::find(depths.begin(), depths.end(), c.target_diopters) == depths.end()) depths.push_back(c.target_diopters);
    if (c.display != "natural" && std::find(displays.begin(), displays.end(), c.display) == displays.end())
      displays.push_back(c.display);
  }
  double y_max = 0.1;
  for (const ContrastCurve& c : curves)
    for (double v : c.contrast) y_max = std::max(y_max, v);
  std::vector<PlotPanel> panels;
  for (double f : frequencies)
    for (double dt : depths) {
      PlotPanel panel;
      char title[64];
      std::snprintf(title, sizeof title, "%.1f cpd, target at %.2f D", f, dt);
      panel.title = title;
      panel.x_label = "accommodation (D)";
      panel.y_label = "normalized contrast";
      panel.y_max = std::ceil(y_max * 10.5) / 10;
      panel.markers.push_back({dt});
      for (const ContrastCurve& c : curves) {
        if (c.frequency != f || c.target_diopters != dt) continue;
        panel.x_min = c.accommodation.front();
        panel.x_max = c.accommodation.back();
        size_t index = std::find(displays.begin(), displays.end(), c.display) - displays.begin();
        panel.lines.push_back({c.display, c.display == "natural" ? "#000" : kColors[index % 7], c.display == "natural",
                               c.accommodation, c.contrast});
      }
      panels.push_back(panel);
    }
  return RenderSvg(panels, static_cast<int>(depths.size()), "Normalized contrast against accommodation");
}

}  // namespace layerlab
