// A scene file: named elements and how they connect along the optical path.
//
//   { "format": "layerlab-scene/1", "name": "...", "description": "...",
//     "subframes": 1, "frame_rate": "60 Hz",
//     "elements": [ { "type": "eye", "name": "eye", "next": "lens", ... },
//                   { "type": "thin_lens", "name": "lens", "next": "bs", ... },
//                   { "type": "half_mirror", "name": "bs",
//                     "transmitted": "near_a", "reflected": "near_b" }, ... ] }
//
// Phases: ParseScene turns JSON into element nodes (built by the registry,
// every key accounted for) with their outgoing connections by name;
// Compile (compile.h) walks the path and produces the DisplaySystem.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "layerlab/elements/registry.h"

namespace layerlab {

inline constexpr const char* kSceneFormat = "layerlab-scene/1";

struct SceneNode {
  std::unique_ptr<Element> element;
  // One entry per element->output_ports(): the name of the next element; empty
  // for a combiner's side with nothing there (null, or an optional port left out).
  std::vector<std::string> outputs;
  Location where;  // of the element's object
};

struct Scene {
  std::string file;
  std::string name;
  std::string description;
  std::vector<SceneNode> nodes;
  int subframes = 1;            // patterns shown per frame, time-multiplexed; the eye sees their mean
  double frame_rate_hz = 60.0;  // Hz, frames (not subframes) per second
  nlohmann::json document;      // the whole parsed file, for later phases

  const SceneNode* find(const std::string& element_name) const;
};

// Keys beyond the element graph that later phases read (target, solver,
// analyses); ParseScene accepts them and leaves their checking to those phases.
const std::vector<std::string>& SceneTaskKeys();

Scene ParseScene(nlohmann::json document, const std::string& file, const ElementRegistry& registry);
Scene LoadScene(const std::string& path, const ElementRegistry& registry);
Scene LoadScene(const std::string& path);  // with the built-in element types

}  // namespace layerlab
