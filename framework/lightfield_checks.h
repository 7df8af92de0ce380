// What every light field is held to, wherever it comes from: a manifest
// (ReadLightField), a target scene, or the Python module (LightFieldGeometry,
// LightField, a solve's target). One definition of the limits, so that an
// array from Python is refused as the same light field in a folder would be.
#pragma once

#include <cstddef>
#include <functional>
#include <string>

#include "layerlab/framework/lightfield.h"

namespace layerlab {

inline constexpr int kMaxViewsPerAxis = 256;
inline constexpr int kMaxPixelsPerAxis = 16384;
inline constexpr size_t kMaxRays = size_t{1} << 31;

// The field of the geometry out of its limits (named as LightFieldGeometry's
// members, "rays" for views x pixels) and why, e.g. ("cols", "must be in [1,
// 16384], got 0"). The limits: origin_z and the window's width and height in
// (0, 1e6] m, its left and top finite, cols and rows in [1, 16384], views_x and
// views_y in [1, 256], the eyebox in [0, 1] m, and at most 2^31 rays, counted
// in checked arithmetic.
using GeometryFailure = std::function<void(const std::string& field, const std::string& why)>;

// Calls `fail` for the first field out of its limits; `fail` must throw.
void CheckLightFieldGeometry(const LightFieldGeometry& g, const GeometryFailure& fail);

// Every value finite and non-negative, as ReadLightField requires of each
// view file (FindValueThatIsNotLight); throws Error("<what>: view 4 (row 1,
// col 1): pixel (row 2, col 3) channel G is NaN; light must be ...") for the
// first that is not. View 4 is the index of the view in LightField::rgb.
void CheckLightFieldValues(const LightField& lf, const std::string& what);

}  // namespace layerlab
