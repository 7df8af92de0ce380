// The eye's view: a planar retina indexed by visual angle, each sample the
// mean over pupil points of the radiance along the ray from the pupil point
// through the in-focus point of that retinal direction.
//
// With accommodation D_a (z_a = 1/D_a) a retinal sample at angles (ax, ay)
// has the in-focus point (z_a tan ax, z_a tan ay, z_a). The ray from pupil
// point u through it meets depth z at tan-angle tan(a) + u (1/z - D_a): at a
// layer of D_k diopters it reads the layer at tan(a) + u (D_k - D_a). So a
// point at depth z blurs over pupil * |1/z - D_a| (tan units): geometric
// optics, finite at D_a = 0 and D_k = 0. A wavefront aberration deviates the
// ray by its slope g(u): it reads the layer at tan(a) + u (D_k - D_a) - g(u).
#pragma once

#include <array>
#include <functional>
#include <string>
#include <vector>

#include "layerlab/framework/exr_image.h"
#include "layerlab/retina/retina_grid.h"
#include "layerlab/retina/retina_workspace.h"
#include "layerlab/retina/scene_radiance.h"
#include "layerlab/systems/display_model.h"
#include "layerlab/systems/lc_response.h"

namespace layerlab {

// The one check of a retina's sampling, for every caller (retina, contrast,
// the run section, Python): each field side in (0, 170] deg, the sample size
// in (0, 10) deg, at most 1e8 samples. Throws layerlab::Error naming
// `field_name` or `resolution_name` (an option, a keyword, a JSON pointer).
void CheckRetinaSampling(double field_x_deg, double field_y_deg, double resolution_deg, const std::string& field_name,
                         const std::string& resolution_name);

// A grid covering `field_x` x `field_y` radians at `resolution` radians per
// sample; the sampling must pass CheckRetinaSampling.
RetinaGrid MakeRetinaGrid(double field_x, double field_y, double resolution);

// The grid turned with the eye: centred on its gaze direction (GazeAngles,
// systems/eye_pose_limits.h), in the display's visual angles.
RetinaGrid CenteredOnGaze(RetinaGrid grid, const EyePose& pose);

// The eye's pupil samples: a cell-centered grid over the pupil's square (a
// round pupil keeps the points inside its circle), jittered within the
// cells, or a Poisson-disk set; a zero pupil is one point at the center.
// Each carries the slope of the eye's wavefront aberration at it, and is
// placed on the eye plane by the eye's pose (elements/eye_pose.h).
std::vector<PupilPoint> PupilSamples(const EyeModel& eye);
// The same points before the eye's pose places them: in the pupil's own
// plane, x right and y up from its centre (what the pupil function sees).
std::vector<PupilPoint> PupilSamplesInOwnPlane(const EyeModel& eye);

// Accommodation per color channel: D_a plus the eye's chromatic defocus, and
// with chromatic_aberration "thibos" plus ThibosDefocus(channel wavelength, reference).
std::array<double, 3> ChannelAccommodation(const EyeModel& eye, double diopters);

// The display: mean over pupil points of sum_b w_b prod_k t_k(tan(a) + u (D_k - D_a)),
// with each layer sampled by its projection's rule. RGB, display-relative units.
Image RetinaOfDisplay(const DisplayModel& model, const Patterns& t, const RetinaGrid& retina,
                      const std::vector<PupilPoint>& pupil, const std::array<double, 3>& accommodation);

struct OneTapTables;
// What the display's retinal image reads of the layers for one retina, pupil
// and accommodation: the retinal directions and, on the one-tap path, each
// layer's column and row taps. They depend on the display's layers, not on
// the light field its model was made for, so one set serves every model of
// the display and every set of patterns (a sweep's curves of one display).
// Images made without a workspace are made in one the tables hold, sized at
// the first for a team of RetinaWorkspace::TeamSize() threads: one such
// image at a time per set of tables.
class DisplayRetinaTables {
 public:
  DisplayRetinaTables(const DisplayModel& model, const RetinaGrid& retina, const std::vector<PupilPoint>& pupil,
                      const std::array<double, 3>& accommodation);
  ~DisplayRetinaTables();
  DisplayRetinaTables(DisplayRetinaTables&&) noexcept;

  // What their images need of a workspace (nothing off the one-tap path), and the one they hold.
  const RetinaWorkspaceSizes& workspace_sizes() const { return sizes_; }
  const RetinaWorkspace& workspace() const { return workspace_; }

 private:
  friend Image RetinaOfDisplay(const DisplayModel&, const Patterns&, const DisplayRetinaTables&);
  friend Image RetinaOfDisplay(const DisplayModel&, const Patterns&, const DisplayRetinaTables&, RetinaWorkspace*);
  RetinaGrid retina_;
  const std::vector<PupilPoint>* pupil_;
  std::array<double, 3> accommodation_;
  size_t layers_, branches_;
  std::vector<double> tan_x_, tan_y_;
  bool one_tap_ = false, same_focus_ = false;
  std::vector<OneTapTables> foci_;  // one-tap path: one focus, or one per channel
  RetinaWorkspaceSizes sizes_;
  mutable RetinaWorkspace workspace_;
};
// The same image from tables made before (for a model of the same display; `pupil` must outlive them).
Image RetinaOfDisplay(const DisplayModel& model, const Patterns& t, const DisplayRetinaTables& tables);
// The same in `workspace`, fitted to the tables first (a sweep's states share one).
Image RetinaOfDisplay(const DisplayModel& model, const Patterns& t, const DisplayRetinaTables& tables,
                      RetinaWorkspace* workspace);
// The time average over a frame of what the panels show (systems/lc_response.h, ShownOverTime): the retina
// is linear in the light, so the instants' images weighted by their shares. One instant: its image.
Image RetinaOfDisplay(const DisplayModel& model, const std::vector<ShownInstant>& shown,
                      const DisplayRetinaTables& tables, RetinaWorkspace* workspace = nullptr);

// The radiance of a light field (LightFieldRadiance) is read image-wise
// (RetinaOfLightField); any other (a traced target, the continuous plane) ray by ray.
Image RetinaOfScene(const SceneRadiance& scene, const RetinaGrid& retina, const std::vector<PupilPoint>& pupil,
                    const std::array<double, 3>& accommodation);
// The general path: the mean over pupil points of `scene` called for every ray, summed in double.
Image RetinaOfSceneRayByRay(const SceneRadiance& scene, const RetinaGrid& retina, const std::vector<PupilPoint>& pupil,
                            const std::array<double, 3>& accommodation);

}  // namespace layerlab
