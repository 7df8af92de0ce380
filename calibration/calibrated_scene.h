// The calibrated scene: the input scene's document with what the calibration
// measured replaced and everything else, key order included, left as it was,
// so that every other command reads it unchanged.
//
// | key          | written for                                | form                              |
// |--------------|--------------------------------------------|-----------------------------------|
// | distance     | a panel with markers behind a lens or curved mirror; every panel behind one whose focal length or gap was fitted (its physical place is what stays) | "72.8123456789 mm", in the place of "virtual_depth" |
// | gap          | the same panels when the scene places them by "gap", or with no lens or curved mirror in front; a lens or curved mirror whose gap was fitted | "12.5 mm" |
// | offset       | a panel with markers                       | ["0.12 mm", "-0.05 mm"]           |
// | rotation     | a panel with markers                       | "0.15 deg"                        |
// | gamma        | a panel with luminance data                | number                            |
// | black_level  | a panel with luminance data                | number                            |
// | focal_length | a lens or curved mirror, when fitted       | "75.0123 mm"                      |
//
// Values carry twelve significant digits, far finer than any measurement, so
// that the file read back gives the fitted numbers to 1e-11.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "layerlab/calibration/calibration.h"
#include "layerlab/systems/scene_document.h"  // RebaseRelativePaths, ReadDocumentInOrder

namespace layerlab {

// `scene` is the document of `file` (named in errors).
nlohmann::ordered_json CalibratedSceneDocument(const nlohmann::ordered_json& scene, const std::string& file,
                                               const CalibratedDisplay& display);

}  // namespace layerlab
