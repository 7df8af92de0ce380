// Scene elements and the registry that builds them by type name.
//
// A scene is read in three visible phases (see systems/scene.h):
//   1. parse: JSON -> element nodes {type, name, parameters, JSON pointer};
//   2. build: each node's type is looked up here and its factory reads its
//      parameters (unit-aware, every key accounted for);
//   3. compile (systems/compile.h): the optical path is walked from the eye
//      outward into the optically equivalent DisplaySystem.
//
// Elements come in a closed set of kinds, because the compile step gives
// each kind a role on the path; types within a kind are open: a new type is
// one file in elements/ and one line in elements/builtin_elements.def
// (the registry is in elements/registry.h).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "layerlab/elements/eye_pose.h"
#include "layerlab/elements/wavefront.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/params.h"
#include "layerlab/framework/polarization.h"

namespace layerlab {
namespace lenses {
class LensSystem;
}

enum class ElementKind { kEye, kLens, kMirror, kCombiner, kInlineOptic, kPanel, kBacklight, kWorld };

// "an eye", "a lens", "a mirror", "a combiner", "an in-line optic", "a panel", "a backlight", "the world".
std::string KindName(ElementKind kind);

class Element {
 public:
  virtual ~Element() = default;
  virtual ElementKind kind() const = 0;
  // Names of the outgoing connections, read from the element's JSON object
  // (each names the next element away from the eye). A backlight and the world have none.
  virtual std::vector<std::string> output_ports() const { return {"next"}; }
  // Those of its ports that a scene may leave out: nothing is seen through them.
  virtual std::vector<std::string> optional_ports() const { return {}; }
  // True when the element acts on polarization (compile then tracks Jones vectors).
  virtual bool polarizing() const { return false; }

  // First-order optics in the path unfolded from the eye (systems/ray_transfer.h):
  // the element's optical power in 1/m (0 for a flat element) ...
  virtual double power() const { return 0; }
  // ... in subframe k of a time-multiplexed display; `powers_given` is how many
  // subframes the element describes (0: the same power in all).
  virtual double power_in_subframe(int k) const { return power(); }
  virtual int powers_given() const { return 0; }

  const std::string& type() const { return type_; }
  const std::string& name() const { return name_; }
  const Location& where() const { return where_; }
  // Path length from the element before it (toward the eye), when the scene
  // gives "gap"; read by the registry for every element between eye and backlight.
  const std::optional<double>& gap() const { return gap_; }

 private:
  friend class ElementRegistry;
  std::string type_, name_;
  Location where_;
  std::optional<double> gap_;
};

// A lens array (elements/lens_array.cpp): identical thin lenslets of the
// element's focal length on a square or hexagonal lattice centred on the axis.
struct LensArraySpec {
  double pitch_m = 0;      // m, lenslet centre to centre
  int cols = 0, rows = 0;  // lenslets across (per row) and down
  double fill = 1;         // each lenslet's clear aperture, as a fraction of its cell
  bool hexagonal = false;  // rows sqrt(3)/2 pitch apart, every other one shifted by half a pitch
};

// A thin lens of either sign, anywhere on the path (paper Eq. 1 for the magnifier).
class LensElement : public Element {
 public:
  ElementKind kind() const final { return ElementKind::kLens; }
  virtual double focal_length() const = 0;                   // m, nonzero; negative diverges
  virtual std::optional<double> clear_aperture() const = 0;  // m, diameter
  double power() const override { return 1.0 / focal_length(); }
  // A focus-tunable lens changes its power from subframe to subframe.
  virtual bool tunable() const { return false; }
  // A lens of real surfaces and glass (elements/lens.cpp), its first vertex
  // nearest the eye, traced exactly by lenses/; none for an ideal thin lens.
  virtual std::shared_ptr<const lenses::LensSystem> lens_system() const { return nullptr; }
  // An array of such lenses, each focal_length(); none for a single lens.
  virtual const LensArraySpec* lens_array() const { return nullptr; }
};

// A real lens's prescription as designed, without its tilt and decentre: the
// first-order optics (the layers' depths and fields) are the centred lens's.
lenses::LensSystem Centred(const lenses::LensSystem& system);

// A fold mirror: it reverses one eye-space axis of what lies behind it and,
// when curved, acts as a lens of power 1/f in the unfolded path (f = R / 2).
class MirrorElement : public Element {
 public:
  ElementKind kind() const final { return ElementKind::kMirror; }
  virtual std::optional<double> focal_length() const = 0;  // m; none for a flat mirror
  virtual bool flips_x() const = 0;
  virtual bool flips_y() const = 0;
  virtual void transfer(Light& light) const = 0;  // its reflectance, toward the eye
  double power() const final { return focal_length() ? 1.0 / *focal_length() : 0.0; }
};

// Splits the path; each output port is one branch toward the panels.
class CombinerElement : public Element {
 public:
  ElementKind kind() const final { return ElementKind::kCombiner; }
  // Whether light it transmits or reflects (`action`, as for transfer) is
  // mirrored about the vertical axis (flip x) or the horizontal axis (flip y) in eye space.
  virtual bool flips_x(size_t action) const = 0;
  virtual bool flips_y(size_t action) const = 0;
  // Applies the combiner to light that it transmits (kTransmittedPort) or
  // reflects (kReflectedPort) toward the eye (elements/splitter_ports.h).
  virtual void transfer(size_t action, Light& light) const = 0;
  // At normal incidence ("fold": "back"): what it reflects returns along the path it came by.
  virtual bool reflects_back() const { return false; }
  // 1/m: the power of its reflection for light meeting its face toward the eye
  // (a curved half mirror); its other face reflects with the opposite power.
  virtual double reflection_power() const { return 0; }
};

// Something light passes through on its way (a wave plate, a filter).
class InlineOpticElement : public Element {
 public:
  ElementKind kind() const final { return ElementKind::kInlineOptic; }
  virtual void transfer(Light& light) const = 0;
};

enum class PupilShape { kSquare, kRound };
enum class PupilSampling { kGrid, kJittered, kPoisson };
enum class ChromaticAberration { kNone, kThibos };
// How the eye's pupil diffracts (docs/eye-model.md): not at all (geometric
// optics), by the diffraction-limited MTF multiplied into the geometric
// image ("mtf"), or by the generalized pupil function ("wave").
enum class EyeDiffraction { kNone, kPupilMtf, kPupilFunction };
// Applegate & Lakshminarayanan's mean Stiles-Crawford coefficient (1993, J. Opt. Soc. Am. A 10:1611), per mm^2.
inline constexpr double kStilesCrawfordRhoPerMm2 = 0.05;

// What sets pupil_diameter when the eye asks for "auto" (eye/pupil_size.h):
// luminance and field default to the display's (compile fills them in).
struct PupilFromLuminance {
  std::optional<double> luminance_cd_m2;           // cd/m2; default half the display's peak white luminance
  std::optional<std::array<double, 2>> field_rad;  // rad, width x height; default the display's field of view
  double age_years = 28.58;                        // years
  int eyes = 1;
};

// The viewer: pupil, its sampling for retinal images, where it sits, and the
// eyebox and views the target light field is sampled over.
struct EyeModel {
  double pupil_diameter_m = 4e-3;  // m; the side of a square pupil; 0 is a pinhole
  PupilShape pupil_shape = PupilShape::kSquare;
  int pupil_samples_x = 9, pupil_samples_y = 9;
  PupilSampling pupil_sampling = PupilSampling::kGrid;
  uint64_t pupil_seed = 1;
  double eye_relief_m = 0.01;  // m, pupil plane to the first lens or curved mirror placed without a "gap"
  double accommodation_min_diopters = 0.0, accommodation_max_diopters = 2.6;  // D
  std::array<double, 3> chromatic_defocus_diopters = {0, 0, 0};               // D added per channel
  double eyebox_width_m = 6e-3, eyebox_height_m = 6e-3;                       // m
  int views_x = 13, views_y = 13;
  // The physiological options; their defaults are the ideal eye.
  ChromaticAberration chromatic_aberration = ChromaticAberration::kNone;
  double reference_wavelength_m = 555e-9;                                 // m, in focus at the accommodation
  std::array<double, 3> channel_wavelengths_m = kChannelWavelengths;      // m, the channels' dominant wavelengths
  std::optional<PupilFromLuminance> pupil_auto;                           // the scene's pupil_diameter "auto"
  double pupil_luminance_used_cd_m2 = 0, pupil_field_area_used_deg2 = 0;  // cd/m2, deg2: what compile gave "auto"
  Wavefront wavefront;
  EyeDiffraction diffraction = EyeDiffraction::kNone;
  double stiles_crawford_rho_per_mm2 = 0;  // per mm^2 (eye/pupil_function.h); 0: no apodization
  EyePose pose;  // the scene's pupil_offset and gaze; retina, contrast and eyebox commands set their own
  std::optional<Binocular> binocular;  // one of two eyes: its pose turns it to the fixation
};

class EyeElement : public Element {
 public:
  explicit EyeElement(EyeModel model) : model_(model) {}
  ElementKind kind() const final { return ElementKind::kEye; }
  const EyeModel& model() const { return model_; }

 private:
  EyeModel model_;
};

// What a non-uniform backlight emits, relative to its luminance, as a layer at
// its plane (elements/backlight.cpp): an image or a pinlight array (fixed: the
// layer's fixed_pattern), or an LED array whose values are solved. An LED
// array's layer is a fine grid of pitch led_pitch / led_stride: each LED's value
// sits at the centre pixel of its led_stride x led_stride cell, every other
// pixel holds 0, and what the eye sees is that grid convolved with the LED's
// spread (systems/source_spread.h).
struct EmitterSpec {
  enum class Kind { kImage, kPinlights, kLeds };
  Kind kind = Kind::kImage;
  std::string description;  // "an array of 12 x 8 pinlights, 3.00 mm apart, 0.20 mm wide", for reports
  int led_stride = 0;       // kLeds: fine pixels per LED along each axis (odd)
  int led_cols = 0, led_rows = 0;
  double spread_fwhm_m = 0;  // kLeds: the full width at half maximum of each LED's (Gaussian) spread, m
  bool solved() const { return kind == Kind::kLeds; }
};

// A transmissive panel as mounted: its pixel grid, the region the images use,
// its photometric response, and its placement on the optical path.
struct PanelSpec {
  double pitch_x_m = 0, pitch_y_m = 0;  // m
  int64_t resolution_cols = 0, resolution_rows = 0;
  int64_t active_cols = 0, active_rows = 0, active_left = 0, active_top = 0;
  Rgb max_transmittance = {1, 1, 1};
  double gamma = 2.2;
  double black_level = 0.0;  // transmittance at input 0, relative to the maximum
  bool reversed = false;     // mounted back to front: mirrored about its vertical axis
  // At most one of the placements is given (the element's "gap" is the third);
  // compile derives the rest.
  std::optional<double> distance_m;    // m from the nearest lens or curved mirror before it
  std::optional<Depth> virtual_depth;  // of the panel's final image, from the eye
  // The active region's center in the panel plane, m from the optical axis,
  // eye-space x right, y up (the scene's "offset"): a point p of the panel's
  // own frame lies at eye_from_panel_m + R(rotation_rad) p.
  std::array<double, 2> eye_from_panel_m = {0, 0};
  double rotation_rad = 0.0;  // rad, in-plane, counterclockwise as the eye sees it
  // rad: the panel turned about x, then about y, through its active region's
  // centre, in the path unfolded from the eye (as a lens's "tilt"); its layer
  // is then mapped (systems/layer_ray_map.h), its first-order optics the untilted panel's.
  std::array<double, 2> tilt_rad = {0, 0};
  bool tilted() const { return tilt_rad[0] != 0 || tilt_rad[1] != 0; }
  double polarization_angle_rad = 0.0;  // rad, axis of the exit polarizer
  // The open fraction of each pixel's rectangular aperture along x and y; 1: no black matrix, no diffraction.
  std::array<double, 2> fill_factor = {1, 1};
  bool diffracts() const { return fill_factor[0] < 1 || fill_factor[1] < 1; }
  // The liquid crystal's 10 to 90 % response times, rising and falling transmittance (s; 0: instant).
  double rise_time_s = 0, fall_time_s = 0;
  // A pattern the layer always shows (a printed mask, a panel held at one image): the active region's
  // transmittance relative to max_transmittance, [row][col][rgb] in the panel's own order, in [0, 1].
  // Null: the layer is solved.
  std::shared_ptr<const std::vector<float>> fixed_pattern;
  std::string fixed_pattern_file;  // as the scene names it, for messages
  // A backlight's emission seen as a layer (elements/backlight.cpp); none for a panel.
  std::optional<EmitterSpec> emitter;
};

class PanelElement : public Element {
 public:
  explicit PanelElement(PanelSpec spec) : spec_(spec) {}
  ElementKind kind() const final { return ElementKind::kPanel; }
  const PanelSpec& spec() const { return spec_; }

 private:
  PanelSpec spec_;
};

class BacklightElement : public Element {
 public:
  explicit BacklightElement(double luminance, double coherence_width_m = 0,
                            std::optional<PanelSpec> emission = std::nullopt)
      : luminance_(luminance), coherence_width_m_(coherence_width_m), emission_(std::move(emission)) {}
  ElementKind kind() const final { return ElementKind::kBacklight; }
  std::vector<std::string> output_ports() const final { return {}; }
  double luminance() const { return luminance_; }                  // cd/m^2
  double coherence_width_m() const { return coherence_width_m_; }  // m; 0: incoherent (systems/panel_diffraction.h)
  // A non-uniform backlight's emission as a layer's grid (its emitter set), placed by the element's "gap"
  // behind the panel in front; none for a uniform backlight.
  const std::optional<PanelSpec>& emission() const { return emission_; }

 private:
  double luminance_;
  double coherence_width_m_;
  std::optional<PanelSpec> emission_;
};

// The world seen through a combiner's port (optical see-through): natural,
// unpolarized light of a uniform luminance, or a scene's (elements/world.cpp).
class WorldElement : public Element {
 public:
  WorldElement(double luminance, std::string scene_file) : luminance_(luminance), scene_file_(std::move(scene_file)) {}
  ElementKind kind() const final { return ElementKind::kWorld; }
  std::vector<std::string> output_ports() const final { return {}; }
  double luminance() const { return luminance_; }  // cd/m^2
  // A target scene (docs/target-format.md) whose radiance, 1 = luminance(), the world shows; empty: uniform.
  const std::string& scene_file() const { return scene_file_; }

 private:
  double luminance_;
  std::string scene_file_;
};

}  // namespace layerlab
