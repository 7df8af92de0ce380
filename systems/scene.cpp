// scene: the top level of a scene file (layerlab-scene/1, systems/scene.h).
//
// | key         | type                | default            | meaning                                        |
// |-------------|---------------------|--------------------|------------------------------------------------|
// | format      | string              | "layerlab-scene/1" | the only format this layerlab reads            |
// | name        | string              | ""                 | shown in reports                               |
// | description | string              | ""                 | shown in reports                               |
// | subframes   | integer             | 1                  | patterns shown per frame (time multiplexing, 1 to 64); the eye sees their mean |
// | frame_rate  | frequency           | 60 Hz              | frames (not subframes) per second, 1-10000 Hz  |
// | elements    | array of elements   | required           | the optical path, each an object with "type" and "name" |
// | solve       | object              | none               | the solver and its target (see solve below)    |
// | run         | object              | none               | what `layerlab run` does (see run below)       |
// | tolerance   | object              | none               | assembly tolerances `layerlab tolerance` draws from (docs/optics.md, Tolerances) |
#include "layerlab/systems/scene.h"

#include <algorithm>

#include <climits>
#include <map>

#include "layerlab/framework/json_file.h"
#include "layerlab/systems/display_system.h"

namespace layerlab {

const SceneNode* Scene::find(const std::string& element_name) const {
  for (const SceneNode& node : nodes)
    if (node.element->name() == element_name) return &node;
  return nullptr;
}

const std::vector<std::string>& SceneTaskKeys() {
  static const std::vector<std::string> keys = {"solve", "run", "tolerance"};
  return keys;
}

Scene ParseScene(nlohmann::json document, const std::string& file, const ElementRegistry& registry) {
  Scene scene;
  scene.file = file;
  scene.document = std::move(document);
  Params top(scene.document, {file, ""});

  std::string format = top.string("format", kSceneFormat);
  if (format != kSceneFormat)
    top.fail("format", "unknown scene format \"" + format + "\"; this layerlab reads \"" + kSceneFormat + "\"");
  scene.name = top.string("name", "");
  scene.description = top.string("description", "");
  scene.subframes = static_cast<int>(top.integer("subframes", 1, kMaxSubframes, 1));
  scene.frame_rate_hz = top.quantity("frame_rate", Dimension::kFrequency, 60.0);
  top.require_range("frame_rate", scene.frame_rate_hz, 1.0, 1e4, false, false);  // below 1 Hz: a slide show
  for (const std::string& key : SceneTaskKeys()) top.mark_read(key);

  const nlohmann::json& elements = top.raw("elements");
  Location elements_at = top.where("elements");
  if (!elements.is_array()) throw Error(elements_at, "expected an array of elements, got " + JsonKindName(elements));
  if (elements.empty()) throw Error(elements_at, "the scene has no elements");
  top.check_all_read();

  std::map<std::string, size_t> index_of_name;
  for (size_t i = 0; i < elements.size(); ++i) {
    Params params(elements[i], elements_at.child(i));
    SceneNode node;
    node.where = params.where();
    node.element = registry.create(params);
    const std::string& name = node.element->name();
    // Names become file names (patterns/<name>.exr, checkpoint/<name>-iteration<N>.exr): they must fit NAME_MAX.
    constexpr size_t kMaxName = NAME_MAX - sizeof("-iteration2147483647.exr") + 1;
    if (name.size() > kMaxName)
      params.fail("name", "element name of " + std::to_string(name.size()) +
                              " bytes; output files are named after "
                              "elements, and the file system allows names of " +
                              std::to_string(NAME_MAX) + " bytes: at most " + std::to_string(kMaxName));
    if (auto [it, fresh] = index_of_name.emplace(name, i); !fresh)
      params.fail("name", "element name \"" + name + "\" is already used by /elements/" + std::to_string(it->second));
    const std::vector<std::string> optional = node.element->optional_ports();
    for (const std::string& port : node.element->output_ports()) {
      const bool may_be_dark = node.element->kind() == ElementKind::kCombiner;  // a light trap behind that side
      const bool left_out = !params.has(port) && std::count(optional.begin(), optional.end(), port);
      if (may_be_dark && (left_out || (params.has(port) && params.raw(port).is_null()))) {
        node.outputs.emplace_back();  // nothing there
        continue;
      }
      std::string target = params.string(port);
      if (target.empty())
        params.fail(port, may_be_dark ? "names no element; null says that nothing is there" : "names no element");
      node.outputs.push_back(target);
    }
    params.check_all_read();
    scene.nodes.push_back(std::move(node));
  }
  return scene;
}

Scene LoadScene(const std::string& path, const ElementRegistry& registry) {
  return ParseScene(ReadJsonFile(path), path, registry);
}

Scene LoadScene(const std::string& path) {
  static const ElementRegistry builtins = ElementRegistry::WithBuiltins();
  return LoadScene(path, builtins);
}

}  // namespace layerlab
