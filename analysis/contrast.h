// Accommodation analysis (the paper's Fig. 5). A texture on a plane at depth
// D_t is the target; each display is factorized for it; the eye focuses over
// a range of accommodation; the normalized contrast at a frequency is the
// Fourier amplitude of the retinal image there divided by that of natural
// viewing focused at D_t. A display supports accommodation when the curve's
// peak follows D_t.
//
// Conventions (docs/accommodation.md), each with the earlier one as an option:
// the reference is natural viewing of the sampled target light field, read
// as the display reads its layers (a perfect display scores 1), or of the
// continuous plane; the grating is uniform in visual angle (f cpd across the
// whole field) or in meters on the plane (f cpd at the line of sight only).
#pragma once

#include <array>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "layerlab/analysis/fourier.h"
#include "layerlab/framework/params.h"
#include "layerlab/solvers/solver.h"
#include "layerlab/systems/display_system.h"
#include "layerlab/systems/layer_sampler.h"
#include "layerlab/systems/scene.h"
#include "layerlab/targets/texture.h"

namespace layerlab {

// The target texture on a plane at depth `depth` carrying `cycles_per_degree`.
using PlaneTextureFactory = std::function<std::shared_ptr<const Texture>(double depth, double cycles_per_degree)>;

enum class GratingSpacing {
  kVisualAngle,  // f cpd at every angle seen from the pupil center
  kPlane,        // f / (depth pi / 180) cycles per meter: f cpd at the line of sight only
};
// A cosine grating of vertical bars, mean * (1 + contrast cos(2 pi f a)), with
// a the visual angle in degrees (kVisualAngle) or its small-angle stand-in s / (depth pi / 180).
PlaneTextureFactory CosineGrating(double mean = 0.5, double contrast = 1.0,
                                  GratingSpacing spacing = GratingSpacing::kVisualAngle);

struct ContrastDisplay {
  std::string name;
  DisplaySystem system;
  std::string solver;     // "" picks by structure: one branch -> multiplicative,
                          // one layer per branch -> additive-trust-region, else hybrid
  SolverOptions options;  // "" solver: that solver's defaults
  bool options_given = false;
  Sampling sampling = Sampling::kNearest;  // the layers' and so natural viewing's
};

// A display for the sweep from its scene file: named after the file, with the
// solver, options and sampling of its "solve" section when it has one.
ContrastDisplay LoadContrastDisplay(const std::string& scene_file);
// The same for a scene already read from `scene_file`.
ContrastDisplay ContrastDisplayOf(const Scene& scene, const std::string& scene_file);

enum class ContrastReference {
  kSampledTarget,  // natural viewing of the target light field the display is asked to show
  kContinuous,     // natural viewing of the continuous textured plane
};
std::string ConventionLabel(ContrastReference reference, GratingSpacing spacing);

// Its keys, flags, Python keywords, ranges and defaults are described once, in
// analysis/contrast_option_table.h.
struct ContrastOptions {
  std::vector<double> target_diopters = {0.7, 1.3, 1.9};
  std::vector<double> frequencies_cpd = {2.0, 4.0};
  double accommodation_min_diopters = 0.0, accommodation_max_diopters = 2.6, accommodation_step_diopters = 0.05;
  double retina_resolution_deg = 0.01;
  double retina_field_deg = 20.0;  // horizontal, centered on field_center_deg
  double field_center_deg = 0.0;   // the window's centre, horizontal, right positive
  int strip_rows = 24;             // light-field rows around the axis (the grating is vertical)
  ContrastReference reference = ContrastReference::kSampledTarget;
  GratingSpacing grating = GratingSpacing::kVisualAngle;  // for the default texture
  PlaneTextureFactory texture;                            // empty: CosineGrating(0.5, 1, grating)
  // Sweep again with the retina moved by half a sample, for each peak's
  // sampling uncertainty; a peak that moves more than flat_limit_diopters (one
  // accommodation step) is "flat": the curve is too flat to place one.
  bool peak_uncertainty = true;
  double flat_limit_diopters = 0.05;
  // Each display's curves also seen from a grid of pupil positions (EyeboxGridOffsets) around its eye's, m:
  // the same factorizations, swept again from each (ContrastCurve::pupil_moved_m). 0: none.
  double eyebox_range_m = 0, eyebox_step_m = 0;
  std::function<void(const std::string&)> progress;
  bool show_progress = false;  // a progress line on stderr (framework/progress.h)

  // False, with "field: value: constraint" in *error, when a value lies
  // outside the table's range or the accommodation sweep is empty.
  bool IsValid(std::string* error) const;
};

inline constexpr double kMaxContrastEyeboxRange = 0.01;  // m
inline constexpr int kMaxContrastEyeboxPupils = 81;

struct ContrastCurve {
  std::string convention;  // ConventionLabel(reference, grating)
  ContrastReference reference = ContrastReference::kSampledTarget;
  std::string display;         // "natural" for natural viewing; "D (factorized for S)" for S's patterns seen through D
  std::string factorized_for;  // the display the patterns were solved on when not this one (S), else ""
  std::string scene;           // the display's own name (its scene's); "" for natural viewing
  std::string eye;             // EyeModelLine of the eye that saw it
  // Seen from the display eye's pupil moved by this (m; ContrastOptions::eyebox_range_m), else {0, 0}.
  std::array<double, 2> pupil_moved_m = {0, 0};
  bool pupil_moved = false;
  // A binocular eye's vergence demand fixating the target on the midline (VergenceDiopters: D_t); NaN for one eye.
  double vergence_diopters = std::numeric_limits<double>::quiet_NaN();
  double target_diopters = 0, frequency = 0;
  std::vector<double> accommodation, contrast;
  std::vector<double> contrast_shifted;  // the retina moved half a sample; empty without peak_uncertainty
  Peak peak;
  PeakEstimate estimate;
  double at_target = 0;            // contrast with the eye focused at D_t (interpolated)
  double reference_amplitude = 0;  // what contrast divides by: natural viewing's amplitude at D_t
  double solve_seconds = 0, sweep_seconds = 0, psnr_db = 0;
  std::string solver;
};

// With `factorized_for`, each display has a second curve per target, named
// FactorizedForName(display, factorized_for): the patterns solved on
// factorized_for's display for the same grating (its solver, options and
// target strip), seen through the display, normalized as its own curve.
std::vector<ContrastCurve> RunContrast(const std::vector<ContrastDisplay>& displays, const ContrastOptions& options,
                                       const ContrastDisplay* factorized_for = nullptr);

// Why a display's peak normalized contrast is above 1, for the report and
// peaks.txt; "" when none is. Against the sampled target (the default): the
// reference reads the light field's pixels on the grating's own plane, in
// focus, and so loses their hold, while the display's layers lie off that
// plane (docs/accommodation.md, "Above 1"). Against the continuous plane: the
// overshoot set beside the display's light-field error.
std::string AboveOneNote(const std::vector<ContrastCurve>& curves);

// "DISPLAY (factorized for OTHER)": no comma, so it is one CSV cell.
std::string FactorizedForName(const std::string& display, const std::string& other);
// "DISPLAY (pupil +1.00 +0.00 mm)": the display's curve seen from its eye's pupil moved so, one CSV cell.
std::string MovedPupilName(const std::string& display, const std::array<double, 2>& moved_m);

// "" when every display (and factorized_for's) can be swept with `options`;
// else "key: value: why", the option named by its key: the retinal window
// (field_center +- retina_field / 2) outside a display's horizontal field,
// which its target strip covers; factorized_for's layers unlike a display's
// (count, each one's pixels, subframes), so its patterns cannot be shown there.
std::string ContrastDisplayProblem(const std::vector<ContrastDisplay>& displays, const ContrastOptions& options,
                                   const ContrastDisplay* factorized_for = nullptr);

// A frequency of the sweep above what a display can show (its finest layer's
// Nyquist frequency, DisplaySystem::max_cpd): one warning per display and
// frequency, since that curve measures aliasing, not the display's contrast.
std::vector<std::string> ContrastWarnings(const std::vector<ContrastDisplay>& displays, const ContrastOptions& options);

// CSV (one row per display, depth, frequency and accommodation), the peak
// table as text, and the Fig. 5 style SVG.
std::string ContrastCsv(const std::vector<ContrastCurve>& curves);
std::string PeakTable(const std::vector<ContrastCurve>& curves);
// The peak table's rows for machines (`layerlab contrast --json`): units in the keys; the uncertainty null
// without the second sweep, the VAC null for one eye or a flat curve.
nlohmann::json PeaksJson(const std::vector<ContrastCurve>& curves);
// ContrastSvg leaves out the curves seen from the eyebox's other pupil positions (analysis/contrast_eyebox.h).
std::string ContrastSvg(const std::vector<ContrastCurve>& curves);

}  // namespace layerlab
