// A target scene (TARGET.json, docs/target-format.md): the light field to
// render (origin plane, window, views) and what it shows, placed in eye space
// (x right, y up, z from the pupil away from the viewer, meters).
//
// Phases: ParseTarget reads every key (unknown keys are refused with a
// suggestion), compiles the display named by "display" when there is one,
// loads meshes and images and places the meshes in eye space. Rendering
// (target_renderer.h) sees only the TargetScene.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "layerlab/framework/json_file.h"
#include "layerlab/framework/lightfield.h"
#include "layerlab/framework/params.h"
#include "layerlab/targets/mesh_io.h"
#include "layerlab/targets/target_motion.h"
#include "layerlab/targets/texture.h"

namespace layerlab {

struct Scene;  // systems/scene.h

inline constexpr const char* kTargetFormat = "layerlab-target/1";

// A fronto-parallel textured rectangle, unlit: its value is its texture.
struct TargetPlane {
  double depth_m = 1.0;              // z, m
  std::array<double, 2> center_m{};  // m; also the texture's origin
  std::array<double, 2> size_m{};    // m
  std::shared_ptr<const Texture> texture;
  bool covers_every_ray = false;  // no "size" given: CoveringSize, and again wherever the scene moves it
};

// A triangle mesh in eye space, Lambertian under the scene's light.
struct TargetMesh {
  std::string file;
  TriangleMesh mesh;                         // positions in eye space, m
  std::shared_ptr<const Texture> texture;    // a constant one for "color"
  double uv_size_m = 1.0;                    // m per unit of texture coordinate
  std::shared_ptr<const MeshMotion> motion;  // its keys, when it moves (TargetSceneAt)
};

// shade = ambient + (1 - ambient) * max(0, n . to_light), n facing the viewer.
struct TargetLight {
  std::array<double, 3> to_light{-0.4, 0.6, -0.7};  // unit vector from the surface toward the light
  double ambient = 0.2;
};

struct TargetScene {
  std::string file;
  LightFieldGeometry geometry;
  int samples_per_pixel = 4;
  uint64_t seed = 1;
  Rgb background{0, 0, 0};
  TargetLight light;
  std::vector<TargetPlane> planes;
  std::vector<TargetMesh> meshes;
  std::string description;  // for the light field's "scene" text
  // Every file the scene reads besides itself (meshes, images), as resolved;
  // the display named by "display" is not listed: its part is `geometry`.
  std::vector<std::string> files_read;
  // The bytes of `file` that were parsed (LoadTarget), which key its render.
  std::optional<FileBytes> file_bytes;
  // How far it lies from where its file places it (MoveTargetScene), m: a binocular eye's own display sees a
  // scene given in the pair's frame from its own axis (elements/eye_pose.h PairFrameInDisplayFrame). Part of
  // its render's key.
  std::array<double, 3> moved_m{};
  // A moving scene's "animation" (its frame rate, the camera's keys), also set when only meshes have keys; and
  // the time it is posed at (TargetSceneAt), part of its render's key.
  std::optional<TargetAnimation> animation;
  double time_s = 0;  // s
};

// The scene at `time_s` (s): each moving mesh placed by its keys, and everything seen from the camera's keyed
// position. ParseTarget poses a moving scene at 0 s, so that every render of it is of a time (part of its
// render's key). A scene that does not move is returned as it is. Refuses a pose that puts a vertex or a plane
// at or behind the pupil plane, naming the time.
TargetScene TargetSceneAt(const TargetScene& scene, double time_s);
// Whether anything in it moves: the camera or a mesh has keys.
bool TargetSceneMoves(const TargetScene& scene);

// "" when every vertex lies in front of the pupil plane (z > 0), else which does not.
std::string InFrontOfThePupil(const std::vector<std::array<double, 3>>& vertices_m);

// Moves every plane (its centre, the texture's origin, and depth) and mesh of `scene` so that it lies `moved_m`
// (m, eye space) from where its file places it; the light field's geometry stays.
void MoveTargetScene(TargetScene* scene, const std::array<double, 3>& moved_m);

// How a target finds the display scene its light field names ("display"):
// LoadScene when empty; a run passes the scene files it has read already.
using SceneReader = std::function<const Scene&(const std::string& path)>;

// `file` names the document in messages; relative paths inside it resolve
// against the file's folder.
TargetScene ParseTarget(const nlohmann::json& document, const std::string& file, const SceneReader& read_scene = {});
TargetScene LoadTarget(const std::string& path, const SceneReader& read_scene = {});

// The smallest rectangle, centered on `center`, that every ray of `g` crosses
// at depth z inside of (with a small margin): the default size of a plane.
std::array<double, 2> CoveringSize(const LightFieldGeometry& g, double z, std::array<double, 2> center);

}  // namespace layerlab
