// The optically equivalent model of a display (paper Fig. 1, right): virtual
// layers in eye space, grouped into branches that add, each a product of its
// layers, seen by an eye. Everything downstream of compile sees only this.
//
// Eye-space conventions (docs/lightfield-format.md): x right, y up, z from
// the pupil into the display, meters; depths are also kept in diopters so
// that a layer at infinity (0 D) stays finite. A layer's pixel grid is
// described in tan-angle units as seen from the pupil center: the pixel
// (row i, col j) of a layer covers tan-angles around
//   eye_from_layer_tan + R(rotation) * ((j + 0.5 - cols/2) * tan_pitch_x, (rows/2 - i - 0.5) * tan_pitch_y),
// with columns counted in the panel's own order after applying flip_x/flip_y.
// Names of placements read destination_from_source and end in their unit (as
// pbrt's renderFromCamera): eye_from_layer_tan_x is the layer grid's center in
// the eye's tan-angle frame; PanelSpec::eye_from_panel_m is the panel's center
// in meters in its own plane, measured from the optical axis.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "layerlab/elements/element.h"
#include "layerlab/systems/ray_transfer.h"

namespace layerlab {

class SampledRayMap;  // systems/layer_ray_map.h
class LensletMap;     // systems/lenslet_map.h

// One element between the eye and a panel, in path order.
struct PathStep {
  std::string element, type;
  ElementKind kind = ElementKind::kLens;
  std::string port;                  // the combiner port this path takes
  std::optional<double> position_m;  // m of unfolded path length from the pupil; none for a flat element without "gap"
  double power_diopters = 0;         // 1/m: lenses and curved mirrors
  bool flips_x = false, flips_y = false;   // mirror reversal (fold mirrors, reflected combiner ports)
  std::optional<double> clear_aperture_m;  // m, diameter
  RayTransfer<double> arrival;             // pupil -> this element, before its own power (placed elements)
  // A real lens: its surfaces (first vertex at position_m) and the axial
  // length to its last vertex; power_diopters is then its paraxial power at
  // the design wavelength (the eye's green channel).
  std::shared_ptr<const lenses::LensSystem> lens_system;
  double axial_length_m = 0;
  std::optional<LensArraySpec> lens_array;  // a lens array's lattice (its lenslets' power is power_diopters)
};

struct VirtualLayer {
  std::string name;            // the panel element, and "@k" (1-based) for subframe k of a time-multiplexed display
  std::string element;         // the panel element
  int subframe = 0;            // 0-based
  int branch = 0;              // index into DisplaySystem::branches
  int position_in_branch = 0;  // 0 is nearest the eye
  double diopters = 0;         // eye-space depth, 1/z
  double depth_m = 0;          // z in m (+inf at 0 D)
  double panel_distance_m =
      0;                  // physical, m: from the nearest lens or curved mirror before it (from the pupil without one)
  double position_m = 0;  // m of unfolded path length from the pupil to the panel
  double magnification = 0;             // M, signed: negative when a real intermediate image inverts it (+-inf at 0 D)
  bool inverted = false;                // M < 0: the image is turned by 180 degrees (both axes flip)
  RayTransfer<double> transfer;         // pupil -> panel, unfolded (mirror reversals kept in flip_x/flip_y)
  std::vector<PathStep> path;           // the elements from the eye to this panel, nearest the eye first
  double pitch_x_m = 0, pitch_y_m = 0;  // virtual pixel pitch at depth z, m (+inf at 0 D)
  double tan_pitch_x = 0, tan_pitch_y = 0;                    // tan-angle per pixel, seen from the pupil center
  int cols = 0, rows = 0;                                     // the active region
  double eye_from_layer_tan_x = 0, eye_from_layer_tan_y = 0;  // the grid center, tan-angle seen from the pupil
  double rotation_rad = 0;                                    // rad
  bool flip_x = false, flip_y = false;                        // panel order against eye-space order
  double fov_x_rad = 0, fov_y_rad = 0;                        // rad, Eq. 2
  double max_cpd = 0;                                         // Nyquist at the grid center
  PanelSpec panel;                                            // as mounted, for panel-ready output
  // Behind a real lens: where each channel's eye ray meets the panel
  // (systems/layer_ray_map.h); the paraxial fields above are the design
  // wavelength's. None through ideal optics (the affine fast path).
  std::shared_ptr<const SampledRayMap> ray_map;
  // Behind a lens array: which lenslet each eye ray passes, and how far that
  // moves it on the grid above (the grid is the image through a lenslet on the axis).
  std::shared_ptr<const LensletMap> lenslets;
};

struct Branch {
  std::string name;  // "bs.reflected", or "main" without a combiner; "@k" for subframe k
  int subframe = 0;
  std::vector<int> layers;  // indices into DisplaySystem::layers, nearest the eye first
  Rgb optics_efficiency{};  // combiners, mirrors and in-line optics, per channel; over subframes, 1/K of it each
  Rgb efficiency{};         // also times every panel's maximum transmittance
  std::string backlight;
  double backlight_luminance_cd_m2 = 0;    // cd/m^2
  double backlight_coherence_width_m = 0;  // m; 0: incoherent (systems/panel_diffraction.h)
};

// Optical see-through: a world element reached through a combiner's port (elements/world.cpp), whose light
// the eye sees added to the display's (systems/world_view.h).
struct WorldView {
  std::string element;                  // the world element
  std::string name;                     // its path, as a branch's: "bs.transmitted"
  double luminance_cd_m2 = 0;           // the world's own
  Rgb efficiency{};                     // unpolarized light through the path to the eye, per channel
  std::string scene_file;               // the world's scene (its radiance, 1 = luminance_cd_m2); empty: uniform
  bool flip_x = false, flip_y = false;  // mirror reversals on its path: the scene is seen mirrored
  std::vector<PathStep> path;           // the elements from the eye to it, nearest the eye first
};

// A folded path's ghost (docs/optics.md, "Paths that pass an element more than once"): a stack seen again by
// another route than its branch's, the light that leaks through a wrong pass. It shows its branch's patterns
// at its own depths and with its own efficiency; the solvers leave it out, the retinal images add it
// (systems/ghosts.h).
struct Ghost {
  std::string name;                  // its route, as a branch's name: "rp.transmitted/hm.transmitted"
  int branch = 0;                    // index into DisplaySystem::branches: the stack it shows again
  std::vector<VirtualLayer> layers;  // one per layer of that branch, in the branch's order (nearest the eye first)
  Rgb optics_efficiency{};           // as a branch's
  Rgb efficiency{};
};

inline constexpr int kMaxSubframes = 64;  // the most subframes a scene may show per frame

struct DisplaySystem {
  std::string name, file;
  std::string eye_name;
  EyeModel eye;
  // The magnifier when every path holds one and the same lens and nothing
  // else with power (the paper's layout); `lens` is empty otherwise.
  std::string lens;
  double focal_length_m = 0;
  std::optional<double> clear_aperture_m;

  std::vector<VirtualLayer> layers;  // farthest first (ascending diopters)
  std::vector<Branch> branches;
  std::vector<WorldView> worlds;  // none for a display that is not see-through
  std::vector<Ghost> ghosts;      // none without a folded path
  // Time multiplexing: K subframes per frame, the eye sees their mean; each
  // subframe's layers and branches are their own (a panel holds K patterns).
  int subframes = 1;          // 1 to kMaxSubframes
  double frame_rate_hz = 60;  // Hz; the panels refresh at subframes x frame_rate_hz

  double fov_x_rad = 0, fov_y_rad = 0;  // rad: the smallest layer field (Eq. 2)
  double max_cpd = 0;                   // the finest layer's Nyquist frequency
  std::optional<double> vignetting_free_fov_x_rad,
      vignetting_free_fov_y_rad;  // rad, from the magnifier's clear aperture

  Rgb peak_luminance_cd_m2{};       // cd/m^2 at full white on every panel
  Rgb brightness_efficiency{};      // luminance at the eye per luminance emitted by the backlights
  double luminance_efficiency = 0;  // the same, Rec.709-luminance weighted

  bool polarization_tracked = false;
  std::vector<std::string> components;  // what this system uses, in words
  std::vector<std::string> warnings;
};

}  // namespace layerlab
