// Renders a target scene into a light field with Embree: view (r, c) is the
// pupil point v = (view_x(c), view_y(r), 0), and pixel (i, j) the rays from v
// through its samples on the shared window of the origin plane (a sheared
// frustum, docs/lightfield-format.md). A pixel's color is the mean of its
// samples; its depth is the eye-space z of the first surface along the ray
// through the pixel center. Shading: target_tracer.h. The work goes row by
// row: a row's rays in each view are one coherent stream, and a plane-wave
// texture's phases at the row's samples serve every view (plane_wave_table.h).
#pragma once

#include <cstdint>
#include <functional>
#include <limits>

#include "layerlab/framework/lightfield.h"
#include "layerlab/targets/target_scene.h"

namespace layerlab {

// Depth of a pixel whose center ray hits nothing. EXR depth channels hold
// finite, non-negative values, so "no surface" is the largest float.
inline constexpr float kBackgroundDepth = std::numeric_limits<float>::max();

struct RenderStats {
  uint64_t rays = 0;   // traced, center rays for depth included
  double seconds = 0;  // wall time, scene build included
};

// Called after each pixel row is done in every view with (rows done, rows in
// all), from the rendering threads (one call at a time is not promised: lock
// if needed).
using RenderProgress = std::function<void(size_t, size_t)>;

LightField RenderTarget(const TargetScene& target, RenderStats* stats = nullptr, const RenderProgress& progress = {});

}  // namespace layerlab
