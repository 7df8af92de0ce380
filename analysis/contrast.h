// Accommodation analysis (the paper's Fig. 5). A texture on a plane at depth
// D_t is the target; each display is factorized for it; the eye focuses over
// a range of accommodation; the normalized contrast at a frequency is the
// Fourier amplitude of the retinal image there divided by that of natural
// viewing focused at D_t. A display supports accommodation when the curve's
// peak follows D_t.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "analysis/fourier.h"
#include "framework/params.h"
#include "solvers/solver.h"
#include "systems/display_system.h"

namespace layerlab {

// Linear RGB of the target texture at a point (s, t) in meters on its plane,
// for a plane at depth `depth` carrying `cycles_per_degree` at the line of sight.
using PlaneTexture = std::function<Rgb(double s, double t)>;
using PlaneTextureFactory = std::function<PlaneTexture(double depth, double cycles_per_degree)>;

// A cosine grating of vertical bars, mean * (1 + contrast cos(2 pi k s)),
// k = f / (depth * pi / 180) cycles per meter: f cpd at the line of sight.
PlaneTextureFactory CosineGrating(double mean = 0.5, double contrast = 1.0);

struct ContrastDisplay {
  std::string name;
  DisplaySystem system;
  std::string solver;      // "" picks by structure: one branch -> multiplicative,
                           // one layer per branch -> additive-trust-region, else hybrid
  SolverOptions options;   // "" solver: that solver's defaults
  bool options_given = false;
};

// A display for the sweep from its scene file: named after the file, with the
// solver and options of its "solve" section when it has one.
ContrastDisplay LoadContrastDisplay(const std::string& scene_file);

struct ContrastOptions {
  std::vector<double> target_diopters = {0.7, 1.3, 1.9};
  std::vector<double> frequencies = {2.0, 4.0};  // cpd
  double accommodation_min = 0.0, accommodation_max = 2.6, accommodation_step = 0.05;  // D
  double retina_resolution = 0.01;  // deg
  double retina_field = 20.0;       // deg, horizontal, centered
  int strip_rows = 24;              // light-field rows around the axis (the grating is vertical)
  PlaneTextureFactory texture = CosineGrating();
  std::function<void(const std::string&)> progress;
};

struct ContrastCurve {
  std::string display;  // "natural" for natural viewing
  double target_diopters = 0, frequency = 0;
  std::vector<double> accommodation, contrast;
  Peak peak;
  double at_target = 0;       // contrast with the eye focused at D_t (interpolated)
  double solve_seconds = 0, sweep_seconds = 0, psnr_db = 0;
  std::string solver;
};

std::vector<ContrastCurve> RunContrast(const std::vector<ContrastDisplay>& displays, const ContrastOptions& options);

// CSV (one row per display, depth, frequency and accommodation), the peak
// table as text, and the Fig. 5 style SVG.
std::string ContrastCsv(const std::vector<ContrastCurve>& curves);
std::string PeakTable(const std::vector<ContrastCurve>& curves);
std::string ContrastSvg(const std::vector<ContrastCurve>& curves);

}  // namespace layerlab
