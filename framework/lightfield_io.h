// The light-field folder of docs/lightfield-format.md: lightfield.json, one
// EXR per view (views/r00_c00.exr) and optional depth maps (depth/...).
#pragma once

#include <string>
#include <vector>

#include "layerlab/framework/content_digest.h"
#include "layerlab/framework/lightfield.h"
#include "layerlab/framework/params.h"

namespace layerlab {

inline constexpr const char* kLightFieldFormat = "lightfield/1";

struct LightFieldReadOptions {
  bool load_depth = true;
  // Only view rows [first_view_row, first_view_row + view_rows) and of each
  // view only pixel rows [first_pixel_row, first_pixel_row + pixel_rows) (one
  // MPI rank's tile, LightFieldGeometry::ViewRows and PixelRows); 0 rows: all.
  int first_view_row = 0, view_rows = 0;
  int first_pixel_row = 0, pixel_rows = 0;
};

// Validates the manifest (format version, sizes, patterns that stay inside
// the folder), then every view file read (present, right size, finite,
// non-negative); no view file beyond the manifest's.
LightField ReadLightField(const std::string& folder, const LightFieldReadOptions& options = {});

// The manifest alone, validated as above.
LightFieldGeometry ReadLightFieldGeometry(const std::string& folder);

// A "window" object (lightfield.json, and a target scene's light_field): the
// origin-plane rectangle {left, top, width, height} in lengths, width and
// height in (0, 1e6] m; every key required, no others.
void ReadLightFieldWindow(Params window, LightFieldGeometry* geometry);

// Writes the folder (creating it), every file atomically, the manifest last;
// returns the files written, relative to `folder`.
std::vector<std::string> WriteLightField(const LightField& lf, const std::string& folder);

// Adds the geometry's numbers to `digest`, to key what was made for one geometry.
ContentDigest& AddGeometry(ContentDigest& digest, const LightFieldGeometry& g);

// The geometry and every value (not the depth or the scene text): tells two
// light fields apart.
std::string LightFieldDigest(const LightField& lf);

}  // namespace layerlab
