// Natural viewing of a light-field target: the radiance along any ray that
// crosses the eyebox, read from the light field itself.
//
// The ray from pupil point u with tan-direction d crosses the origin plane at
// x = u + d z_lf (docs/lightfield-format.md). Its value is interpolated
// bilinearly over the four views around u, and in each view read at x by the
// layers' sampling rule (layer_sampler.h): nearest (the default, as the
// display's layers are read) holds the pixel containing x, bilinear blends the
// four pixel centers around it. So a one-layer display on the origin plane
// whose pixels are the light field's is seen exactly as natural viewing of its
// own light field, under either rule. A pupil point outside the eyebox reads
// the nearest edge views; a ray outside the window reads 0. A 4 mm pupil
// inside the paper's 6 mm eyebox of 13 x 13 views needs no extrapolation.
#pragma once

#include <array>
#include <vector>

#include "layerlab/framework/exr_image.h"
#include "layerlab/framework/lightfield.h"
#include "layerlab/retina/retina_grid.h"
#include "layerlab/retina/retina_workspace.h"
#include "layerlab/retina/scene_radiance.h"
#include "layerlab/systems/layer_sampler.h"

namespace layerlab {

// The radiance of one ray, as above. RetinaOfScene recognizes it inside a
// SceneRadiance and takes RetinaOfLightField instead of calling it per ray.
class LightFieldRays {
 public:
  LightFieldRays(const LightField& lf, Sampling pixels) : lf_(&lf), pixels_(pixels) {}
  std::array<double, 3> operator()(const PupilPoint& u, double dx, double dy) const;
  const LightField& light_field() const { return *lf_; }
  Sampling sampling() const { return pixels_; }

 private:
  const LightField* lf_;
  Sampling pixels_;
};

// The returned function refers to `lf`, which must outlive it.
SceneRadiance LightFieldRadiance(const LightField& lf, Sampling pixels = Sampling::kNearest);

// RetinaOfScene of LightFieldRadiance(lf, pixels), image-wise: for one pupil
// point the column a ray reads depends only on the retinal column and its
// row only on the retinal row, and the views it blends only on the pupil
// point; so each retinal row blends, per pupil point, the few view rows it
// reads into one row and gathers the retinal columns from it. Sums in float
// (within 1e-5 relative of the per-ray sums in double; tests/natural_viewing_test.cpp).
Image RetinaOfLightField(const LightField& lf, Sampling pixels, const RetinaGrid& retina,
                         const std::vector<PupilPoint>& pupil, const std::array<double, 3>& accommodation);
// The same in `workspace`, fitted to LightFieldRetinaSizes(lf.geometry, retina, pupil) first.
Image RetinaOfLightField(const LightField& lf, Sampling pixels, const RetinaGrid& retina,
                         const std::vector<PupilPoint>& pupil, const std::array<double, 3>& accommodation,
                         RetinaWorkspace* workspace);

}  // namespace layerlab
