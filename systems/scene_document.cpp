#include "layerlab/systems/scene_document.h"

#include <filesystem>
#include <fstream>
#include <sstream>

#include "layerlab/framework/error.h"

namespace layerlab {

using nlohmann::ordered_json;

std::vector<std::string> ScenePathPointers(const ordered_json& scene) {
  std::vector<std::string> pointers;
  auto object = [](const ordered_json& parent, const char* key) -> const ordered_json* {
    return parent.is_object() && parent.contains(key) && parent[key].is_object() ? &parent[key] : nullptr;
  };
  if (const ordered_json* solve = object(scene, "solve"))
    for (const char* key : {"target", "target_scene"})
      if (solve->contains(key) && (*solve)[key].is_string()) pointers.push_back(std::string("/solve/") + key);
  if (const ordered_json* run = object(scene, "run"))
    for (const char* section : {"compare", "contrast"})
      if (const ordered_json* s = object(*run, section); s && s->contains("scenes") && (*s)["scenes"].is_array())
        for (size_t i = 0; i < (*s)["scenes"].size(); ++i)
          if ((*s)["scenes"][i].is_string())
            pointers.push_back(std::string("/run/") + section + "/scenes/" + std::to_string(i));
  // The files elements read beside the scene: a lens's prescription, a panel's fixed pattern, a backlight's
  // emission image, a world's scene.
  if (scene.is_object() && scene.contains("elements") && scene["elements"].is_array())
    for (size_t i = 0; i < scene["elements"].size(); ++i) {
      const ordered_json& e = scene["elements"][i];
      const std::string at = "/elements/" + std::to_string(i) + "/";
      for (const char* key : {"prescription", "fixed_pattern", "scene"})
        if (e.is_object() && e.contains(key) && e[key].is_string()) pointers.push_back(at + key);
      if (const ordered_json* pattern = e.is_object() ? object(e, "pattern") : nullptr;
          pattern && pattern->contains("file") && (*pattern)["file"].is_string())
        pointers.push_back(at + "pattern/file");
    }
  return pointers;
}

void RebaseRelativePaths(ordered_json& scene, const std::string& from_file, const std::string& to_file) {
  namespace fs = std::filesystem;
  // The folders, absolute: a bare file name has an empty parent, which fs::absolute refuses.
  const fs::path from = fs::absolute(from_file).parent_path(), to = fs::absolute(to_file).parent_path();
  for (const std::string& pointer : ScenePathPointers(scene)) {
    ordered_json& value = scene[ordered_json::json_pointer(pointer)];
    const fs::path path = value.get<std::string>();
    if (path.is_absolute()) continue;
    value = (from / path).lexically_normal().lexically_relative(to.lexically_normal()).generic_string();
  }
}

ordered_json ReadDocumentInOrder(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path + ": cannot open for reading");
  std::ostringstream text;
  text << in.rdbuf();
  try {
    return ordered_json::parse(text.str());
  } catch (const ordered_json::exception& e) {
    throw Error(path + ": malformed JSON: " + e.what());
  }
}

void RequireScenePointer(const nlohmann::ordered_json& scene, const std::string& scene_file, const std::string& pointer,
                         const Location& at, const std::string& noun, const std::string& example) {
  bool present = false;
  try {
    present = scene.contains(nlohmann::ordered_json::json_pointer(pointer));
  } catch (const nlohmann::ordered_json::exception&) {
    throw Error(at, "\"" + pointer + "\" is not a JSON pointer (\"" + example + "\")");
  }
  if (pointer.empty()) throw Error(at, "the whole scene cannot be " + noun);
  if (!present)
    throw Error(at, "\"" + pointer + "\" is not in the scene " + scene_file + " (" + noun +
                        " replaces a value the base scene has; add it there with a default)");
}

}  // namespace layerlab
