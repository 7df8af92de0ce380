// The light field of one textured plane, computed directly (no ray tracer):
// ray (x, v) meets the plane at depth z at p = v + (x - v) z / z_lf
// (docs/lightfield-format.md) and reads the texture there. This is what the
// contrast analysis renders in-process for a grating at depth D_t; the
// Embree renderer gives the same values for the same plane (tested).
#pragma once

#include <array>
#include <cstdint>

#include "layerlab/framework/lightfield.h"
#include "layerlab/targets/texture.h"

namespace layerlab {

struct PlaneSampling {
  int samples_per_pixel = 1;  // 1: the pixel center; more: stratified, jittered (pixel_sampling.h)
  uint64_t seed = 1;
};

// An unbounded plane at depth z (m) whose texture origin is at (center_x, center_y).
// Depth maps hold z everywhere.
LightField RenderPlaneLightField(const LightFieldGeometry& g, double z, const Texture& texture,
                                 const PlaneSampling& sampling = {}, std::array<double, 2> center = {0, 0});

}  // namespace layerlab
