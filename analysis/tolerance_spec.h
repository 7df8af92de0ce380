// Assembly tolerances for `layerlab tolerance` (docs/optics.md, "Tolerances"):
// read from the scene's "tolerance" object or a file of the same object,
//
//   { "panel_decentre": "0.05 mm", "panel_tilt": "0.2 deg", "lens_decentre": "0.05 mm",
//     "lens_tilt": "0.1 deg", "gap": "0.1 mm", "focal_length": "1 %" }
//
// each a limit applied independently to every panel, lens, gap or focal
// length of the scene (per axis for decentres and tilts), and drawn as
// Zemax's Monte Carlo draws by default: normal with the limit as 2 sigma,
// truncated at the limit (redrawn beyond it).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "layerlab/framework/error.h"
#include "layerlab/framework/random.h"

namespace layerlab {

enum class ToleranceKind { kPanelDecentre, kPanelTilt, kLensDecentre, kLensTilt, kGap, kFocalLength };
inline constexpr int kToleranceKinds = 6;

// The key ("panel_decentre", ...) and what the value is ("a length", ...).
std::string ToleranceKey(ToleranceKind kind);
// Whether the calibration fit (calibration/calibration.h) can measure it, and how, in words.
std::string CalibrationMeasures(ToleranceKind kind);
bool CalibrationCanMeasure(ToleranceKind kind);

struct Tolerance {
  ToleranceKind kind = ToleranceKind::kGap;
  double limit = 0;  // m for decentres and gaps, rad for tilts, a fraction for focal lengths
};

struct ToleranceSpec {
  std::vector<Tolerance> tolerances;  // in the order of ToleranceKind, those given
  std::string source;                 // "scene.json: /tolerance" or the file
};

// Reads a tolerance object at `where`; throws layerlab::Error naming the file
// and pointer for an unknown key, a wrong unit, a negative, zero-free NaN or
// infinite value, or an empty object.
ToleranceSpec ReadToleranceSpec(const nlohmann::json& object, const Location& where);
// The scene document's "tolerance" object (pointer /tolerance), or the file's whole document.
ToleranceSpec ReadToleranceFile(const std::string& path);

// One draw of a truncated normal of sigma = limit / 2 in [-limit, limit]
// (a zero limit draws 0).
double DrawTruncatedNormal(Gaussian& random, double limit);

}  // namespace layerlab
