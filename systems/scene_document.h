// A scene file's document as JSON that keeps the file's key order, and the
// relative paths in it re-expressed for a copy written elsewhere: what
// `layerlab fit` (the calibrated scene) and `layerlab sweep` (a job's scene)
// write next to other files than the scene they started from.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "layerlab/framework/error.h"

namespace layerlab {

// Every relative path of a scene ("solve": "target", "target_scene"; "run":
// "compare" and "contrast" "scenes") re-expressed from the folder of
// `from_file` (the input scene) to that of `to_file` (the calibrated one), so
// that the calibrated scene finds the same files wherever it is written.
// Either file may be a bare name (relative to the working directory).
void RebaseRelativePaths(nlohmann::ordered_json& scene, const std::string& from_file, const std::string& to_file);

// A scene file's document with its keys in file order (LoadScene has checked it).
nlohmann::ordered_json ReadDocumentInOrder(const std::string& path);

// Refuses, at `at`, a `pointer` that is not a JSON pointer, is the whole
// scene, or names no value of `scene` (the document of `scene_file`): what a
// sweep's parameter and a design's variable replace must be there. `noun`
// says what replaces it ("a parameter"), `example` shows a good pointer.
void RequireScenePointer(const nlohmann::ordered_json& scene, const std::string& scene_file, const std::string& pointer,
                         const Location& at, const std::string& noun, const std::string& example);

// The JSON pointers of the relative-path values RebaseRelativePaths rebases, in `scene`.
std::vector<std::string> ScenePathPointers(const nlohmann::ordered_json& scene);

}  // namespace layerlab
