#include "layerlab/targets/target_scene.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <optional>

#include "layerlab/framework/json_file.h"
#include "layerlab/framework/lightfield_io.h"
#include "layerlab/systems/compile.h"
#include "layerlab/targets/length_or_angle.h"

namespace layerlab {
namespace {

using nlohmann::json;

constexpr int kMaxViewsPerAxis = 256;
constexpr int kMaxPixelsPerAxis = 16384;
constexpr size_t kMaxObjects = 4096;
constexpr size_t kMaxKeys = 100000;

std::string Diopters(double z) { return FormatFixed(1.0 / z, 2) + " D"; }

// A depth given as "1.3 D" or "0.77 m", strictly in front of the eye and finite.
double RequiredDepth(Params& p, const std::string& key) {
  std::optional<Depth> d = p.optional_depth(key);
  if (!d) p.raw(key);  // throws: missing required key
  if (!(d->diopters > 0)) p.fail(key, "must be nearer than infinity (more than 0 D)");
  if (d->diopters > 1000) p.fail(key, "is nearer than 1 mm to the eye");
  return 1.0 / d->diopters;
}

// Reads a JSON array of exactly `n` values as a Params with keys "0", "1", ...
Params ArrayParams(Params& p, const std::string& key, size_t n, const std::string& expected) {
  const json& v = p.raw(key);
  if (!v.is_array() || v.size() != n) p.fail(key, "expected " + expected + ", got " + v.dump());
  json object = json::object();
  for (size_t i = 0; i < n; ++i) object[std::to_string(i)] = v[i];
  return Params(std::move(object), p.where(key));
}

// z of a position: a length ("770 mm", or a number in meters) or a depth ("1.3 D").
double DepthOrLength(Params& p, const std::string& key) {
  const json& v = p.raw(key);
  if (v.is_string()) {
    std::string text = v.get<std::string>();
    try {
      return ParseQuantity(text, Dimension::kLength);
    } catch (const Error&) {
    }
    std::optional<Depth> d = p.optional_depth(key);
    if (!(d->diopters > 0)) p.fail(key, "must be nearer than infinity (more than 0 D)");
    return 1.0 / d->diopters;
  }
  return p.quantity(key, Dimension::kLength);
}

LightFieldGeometry ParseLightField(Params& lf, const std::string& base_dir, const SceneReader& read_scene) {
  LightFieldGeometry g;
  g.origin_z_m = RequiredDepth(lf, "origin_plane");

  std::vector<std::string> window_keys;
  for (const char* key : {"field_of_view", "window", "display"})
    if (lf.has(key)) window_keys.push_back(key);
  if (window_keys.empty())
    throw Error(lf.where(), "the light field needs its window: give \"field_of_view\", \"window\" or \"display\"");
  if (window_keys.size() > 1)
    lf.fail(window_keys[1], "\"" + window_keys[0] +
                                "\" already sets the window; give only one of "
                                "\"field_of_view\", \"window\" and \"display\"");

  std::optional<std::array<int64_t, 2>> default_resolution;
  if (lf.has("display")) {
    std::string display = lf.string("display");
    std::string path = (std::filesystem::path(base_dir) / display).string();
    if (!std::filesystem::exists(path)) lf.fail("display", "no such scene file: " + path);
    DisplaySystem system = read_scene ? Compile(read_scene(path)) : Compile(LoadScene(path));
    for (const char* key : {"views", "eyebox"})
      if (lf.has(key))
        lf.fail(key, std::string("comes from the display (\"display\": \"") + display + "\"); remove it here");
    g.views_x = system.eye.views_x;
    g.views_y = system.eye.views_y;
    g.eyebox_width_m = system.eye.eyebox_width_m;
    g.eyebox_height_m = system.eye.eyebox_height_m;
    g.window_width_m = 2 * g.origin_z_m * std::tan(system.fov_x_rad / 2);
    g.window_height_m = 2 * g.origin_z_m * std::tan(system.fov_y_rad / 2);
    g.window_left_m = -g.window_width_m / 2;
    g.window_top_m = g.window_height_m / 2;
    // The panel with the narrowest field (the farthest) sets the resolution; a backlight's emission grid
    // (elements/backlight.cpp) is not an image's.
    double narrowest = INFINITY;
    for (const VirtualLayer& layer : system.layers)
      if (!layer.panel.emitter && layer.fov_x_rad < narrowest) {
        narrowest = layer.fov_x_rad;
        default_resolution = std::array<int64_t, 2>{layer.cols, layer.rows};
      }
  } else {
    if (lf.has("field_of_view")) {
      Params fov = ArrayParams(lf, "field_of_view", 2, "two angles [horizontal, vertical]");
      double fov_x = fov.quantity("0", Dimension::kAngle), fov_y = fov.quantity("1", Dimension::kAngle);
      fov.require_range("0", fov_x, 0.0, std::numbers::pi, true, true);
      fov.require_range("1", fov_y, 0.0, std::numbers::pi, true, true);
      g.window_width_m = 2 * g.origin_z_m * std::tan(fov_x / 2);
      g.window_height_m = 2 * g.origin_z_m * std::tan(fov_y / 2);
      g.window_left_m = -g.window_width_m / 2;
      g.window_top_m = g.window_height_m / 2;
    } else {
      ReadLightFieldWindow(lf.object("window"), &g);
    }
    std::array<int64_t, 2> views = lf.integer_pair("views", 1, kMaxViewsPerAxis);
    g.views_x = static_cast<int>(views[0]);
    g.views_y = static_cast<int>(views[1]);
    lf.raw("eyebox");  // required
    std::array<double, 2> eyebox = lf.quantity_pair("eyebox", Dimension::kLength, {0, 0});
    lf.require_range("eyebox", eyebox[0], 0.0, 0.1, false, false);
    lf.require_range("eyebox", eyebox[1], 0.0, 0.1, false, false);
    g.eyebox_width_m = eyebox[0];
    g.eyebox_height_m = eyebox[1];
  }

  std::array<int64_t, 2> resolution = default_resolution && !lf.has("resolution")
                                          ? *default_resolution
                                          : lf.integer_pair("resolution", 1, kMaxPixelsPerAxis);
  lf.mark_read("resolution");
  g.cols = static_cast<int>(resolution[0]);
  g.rows = static_cast<int>(resolution[1]);
  if (g.ray_count() > (size_t{1} << 31))
    throw Error(lf.where(),
                std::to_string(g.ray_count()) + " rays (views x pixels) is beyond the 2^31 this layerlab handles");
  lf.check_all_read();
  return g;
}

// A rotation: three angles [about x, about y, about z].
Vec3 Angles(Params& p, const std::string& key) {
  Params angles = ArrayParams(p, key, 3, "three angles [about x, about y, about z]");
  return {angles.quantity("0", Dimension::kAngle), angles.quantity("1", Dimension::kAngle),
          angles.quantity("2", Dimension::kAngle)};
}

// The keys of an object's motion or of the camera: [{"time", "position", "rotation"}, ...] in time order.
std::vector<MotionKey> ParseKeys(Params& p, const std::string& name, bool rotations) {
  const json& list = p.raw(name);
  if (!list.is_array() || list.empty())
    p.fail(name, "expected an array of keys [{\"time\": \"0 s\", \"position\": [x, y, z]}, ...], got " + list.dump());
  if (list.size() > kMaxKeys)
    p.fail(name, std::to_string(list.size()) + " keys; the limit is " + std::to_string(kMaxKeys));
  std::vector<MotionKey> keys;
  const Location at = p.where(name);
  for (size_t i = 0; i < list.size(); ++i) {
    Params k(list[i], at.child(i));
    MotionKey key;
    key.time_s = k.quantity("time", Dimension::kTime);
    k.require_range("time", key.time_s, 0.0, 1e6, false, false);
    if (!keys.empty() && !(key.time_s > keys.back().time_s))
      k.fail("time",
             "keys must come in increasing time; the key before is at " + FormatFixed(keys.back().time_s, 4) + " s");
    if (k.has("position")) {
      Params xyz = ArrayParams(k, "position", 3, "[x, y, z]: lengths, z also as a depth such as \"1 D\"");
      key.position_m = Vec3{xyz.quantity("0", Dimension::kLength), xyz.quantity("1", Dimension::kLength),
                            rotations ? DepthOrLength(xyz, "2") : xyz.quantity("2", Dimension::kLength)};
    }
    if (rotations && k.has("rotation")) key.rotation_rad = Angles(k, "rotation");
    k.mark_read("position");
    if (rotations) k.mark_read("rotation");
    k.check_all_read();
    if (!key.position_m && !key.rotation_rad)
      throw Error(k.where(), rotations ? "a key gives a \"position\", a \"rotation\" or both"
                                       : "a camera key gives a \"position\"");
    keys.push_back(key);
  }
  return keys;
}

TargetAnimation ParseAnimation(Params& a) {
  TargetAnimation animation;
  animation.frame_rate_hz = a.quantity("frame_rate", Dimension::kFrequency, animation.frame_rate_hz);
  a.require_range("frame_rate", animation.frame_rate_hz, 0.0, 1e4, true, false);
  if (a.has("camera")) animation.camera = ParseKeys(a, "camera", /*rotations=*/false);
  a.check_all_read();
  return animation;
}

TargetPlane ParsePlane(Params& o, const LightFieldGeometry& g, const std::string& base_dir, std::string& description,
                       std::vector<std::string>& files_read) {
  TargetPlane plane;
  plane.depth_m = RequiredDepth(o, "depth");
  plane.center_m = o.quantity_pair("center", Dimension::kLength, {0, 0});
  plane.covers_every_ray = !o.has("size");
  plane.size_m =
      o.has("size") ? LengthOrAnglePair(o, "size", plane.depth_m) : CoveringSize(g, plane.depth_m, plane.center_m);
  o.mark_read("size");
  double scale = plane.depth_m / g.origin_z_m;
  TextureFrame frame{plane.depth_m, {g.window_width_m * scale, g.window_height_m * scale}, base_dir, &files_read};
  Params texture = o.object("texture");
  plane.texture = ParseTexture(texture, frame);
  o.check_all_read();
  description = "plane at " + Diopters(plane.depth_m) + " (" + plane.texture->Describe() + ")";
  return plane;
}

TargetMesh ParseMesh(Params& o, const std::string& base_dir, std::string& description,
                     std::vector<std::string>& files_read) {
  TargetMesh target;
  target.file = o.string("file");
  std::string path = (std::filesystem::path(base_dir) / target.file).string();
  target.mesh = ReadMesh(path);
  files_read.push_back(path);

  double scale = o.quantity("scale", Dimension::kLength, 1.0);
  o.require_range("scale", scale, 0.0, 1e3, true, false);
  const Vec3 angles = o.has("rotation") ? Angles(o, "rotation") : Vec3{0, 0, 0};
  o.mark_read("rotation");
  Params position_params = ArrayParams(o, "position", 3, "[x, y, z]: lengths, z also as a depth such as \"1 D\"");
  Vec3 position{position_params.quantity("0", Dimension::kLength), position_params.quantity("1", Dimension::kLength),
                DepthOrLength(position_params, "2")};
  position_params.require_range("2", position[2], 0.0, 1e3, true, false);

  std::vector<Vec3> local(target.mesh.positions.size());
  Vec3 lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
  for (size_t i = 0; i < local.size(); ++i) {
    const Vec3& p = target.mesh.positions[i];
    local[i] = {p[0] * scale, p[1] * scale, p[2] * scale};
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], local[i][k]), hi[k] = std::max(hi[k], local[i][k]);
  }
  PlaceVertices(local, position, angles, &target.mesh.positions);
  if (const std::string why = InFrontOfThePupil(target.mesh.positions); !why.empty())
    o.fail("position", path + ": " + why);
  if (o.has("keys")) {
    auto motion = std::make_shared<MeshMotion>();
    motion->local_m = std::move(local);
    motion->position_m = position;
    motion->rotation_rad = angles;
    motion->keys = ParseKeys(o, "keys", /*rotations=*/true);
    target.motion = std::move(motion);
  }
  // The mesh's own size (before rotation), so turning a mesh keeps its texture.
  double extent = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
  target.uv_size_m = o.quantity("uv_size", Dimension::kLength, extent > 0 ? extent : 1.0);
  o.require_range("uv_size", target.uv_size_m, 0.0, 1e3, true, false);

  if (o.has("color") && o.has("texture")) o.fail("texture", "give \"color\" or \"texture\", not both");
  if (o.has("texture")) {
    if (!target.mesh.has_uvs())
      o.fail("texture", path + " has no texture coordinates (OBJ vt, PLY u v); give it a \"color\" instead");
    TextureFrame frame{position[2], {target.uv_size_m, target.uv_size_m}, base_dir, &files_read};
    Params texture = o.object("texture");
    target.texture = ParseTexture(texture, frame);
  } else {
    target.texture = MakeConstantTexture(o.fraction_rgb("color", 0.8));
  }
  o.check_all_read();
  description = "mesh " + target.file + " at " + Diopters(position[2]) + " (" +
                std::to_string(target.mesh.triangles.size()) + " triangles)";
  return target;
}

TargetLight ParseLight(Params& l) {
  TargetLight light;
  if (l.has("direction_to_light")) {
    Params d = ArrayParams(l, "direction_to_light", 3, "three numbers [x, y, z]");
    Vec3 v{d.quantity("0", Dimension::kFraction), d.quantity("1", Dimension::kFraction),
           d.quantity("2", Dimension::kFraction)};
    double norm = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (!(norm > 0) || !std::isfinite(norm)) l.fail("direction_to_light", "must be a non-zero, finite direction");
    light.to_light = {v[0] / norm, v[1] / norm, v[2] / norm};
  }
  l.mark_read("direction_to_light");
  light.ambient = l.quantity("ambient", Dimension::kFraction, light.ambient);
  l.require_range("ambient", light.ambient, 0.0, 1.0, false, false);
  l.check_all_read();
  return light;
}

}  // namespace

std::string InFrontOfThePupil(const std::vector<Vec3>& vertices_m) {
  for (size_t i = 0; i < vertices_m.size(); ++i)
    if (!(vertices_m[i][2] > 0))
      return "vertex " + std::to_string(i) + " lands at z = " + FormatFixed(vertices_m[i][2], 4) +
             " m, not in front of the pupil plane (z > 0)";
  return "";
}

namespace {

std::string AtTime(double time_s) { return "at " + FormatFixed(time_s, 4) + " s"; }

// `scene` at `time_s`, its still objects now seen from `camera_now_m`.
TargetScene Posed(const TargetScene& scene, const Vec3& camera_now_m, double time_s) {
  TargetScene posed = scene;
  posed.time_s = time_s;
  const Vec3 camera = PositionAt(scene.animation->camera, time_s, {0, 0, 0});
  const Vec3 by{camera[0] - camera_now_m[0], camera[1] - camera_now_m[1], camera[2] - camera_now_m[2]};
  for (TargetMesh& mesh : posed.meshes) {
    if (mesh.motion) {
      const MeshMotion& m = *mesh.motion;
      PlaceVertices(m.local_m, PositionAt(m.keys, time_s, m.position_m), RotationAt(m.keys, time_s, m.rotation_rad),
                    &mesh.mesh.positions);
      for (Vec3& p : mesh.mesh.positions)
        for (int k = 0; k < 3; ++k) p[k] += scene.moved_m[k] - camera[k];
    } else {
      for (Vec3& p : mesh.mesh.positions)
        for (int k = 0; k < 3; ++k) p[k] -= by[k];
    }
    if (const std::string why = InFrontOfThePupil(mesh.mesh.positions); !why.empty())
      throw Error(scene.file + ": " + AtTime(time_s) + ", mesh " + mesh.file + ": " + why);
  }
  for (size_t i = 0; i < posed.planes.size(); ++i) {
    TargetPlane& plane = posed.planes[i];
    plane.center_m[0] -= by[0], plane.center_m[1] -= by[1];
    plane.depth_m -= by[2];
    if (!(plane.depth_m > 0))
      throw Error(scene.file + ": " + AtTime(time_s) + ", the camera has passed the plane the file places at " +
                  FormatFixed(scene.planes[i].depth_m +
                                  PositionAt(scene.animation->camera, scene.time_s, {0, 0, 0})[2] - scene.moved_m[2],
                              4) +
                  " m (it would lie " + FormatFixed(plane.depth_m, 4) + " m from the pupil plane)");
    if (plane.covers_every_ray) plane.size_m = CoveringSize(scene.geometry, plane.depth_m, plane.center_m);
  }
  return posed;
}

}  // namespace

TargetScene TargetSceneAt(const TargetScene& scene, double time_s) {
  if (!scene.animation) return scene;
  return Posed(scene, PositionAt(scene.animation->camera, scene.time_s, {0, 0, 0}), time_s);
}

bool TargetSceneMoves(const TargetScene& scene) {
  if (!scene.animation) return false;
  if (!scene.animation->camera.empty()) return true;
  return std::any_of(scene.meshes.begin(), scene.meshes.end(), [](const TargetMesh& m) { return m.motion != nullptr; });
}

std::array<double, 2> CoveringSize(const LightFieldGeometry& g, double z, std::array<double, 2> center) {
  double s = z / g.origin_z_m;
  auto half_extent = [&](double x0, double x1, double eyebox, double c) {
    double half = 0;
    for (double x : {x0, x1})
      for (double v : {-eyebox / 2, eyebox / 2}) half = std::max(half, std::abs(v * (1 - s) + x * s - c));
    return half;
  };
  double half_w = half_extent(g.window_left_m, g.window_left_m + g.window_width_m, g.eyebox_width_m, center[0]);
  double half_h = half_extent(g.window_top_m - g.window_height_m, g.window_top_m, g.eyebox_height_m, center[1]);
  const double margin = 1.02;  // beyond every ray, float rounding included
  return {2 * half_w * margin, 2 * half_h * margin};
}

TargetScene ParseTarget(const json& document, const std::string& file, const SceneReader& read_scene) {
  Params p(document, {file, ""});
  const std::string base_dir = std::filesystem::path(file).parent_path().string();
  TargetScene target;
  target.file = file;
  std::string format = p.string("format");
  if (format != kTargetFormat)
    p.fail("format", "unknown target format \"" + format + "\"; this layerlab reads \"" + kTargetFormat + "\"");
  std::string description = p.string("description", "");

  Params lf = p.object("light_field");
  target.geometry = ParseLightField(lf, base_dir, read_scene);
  target.samples_per_pixel = static_cast<int>(p.integer("samples_per_pixel", 1, 1024, 4));
  target.seed = static_cast<uint64_t>(p.integer("seed", 0, INT64_MAX, 1));
  target.background = p.fraction_rgb("background", 0.0);
  if (p.has("light")) {
    Params light = p.object("light");
    target.light = ParseLight(light);
  }
  if (p.has("animation")) {
    Params animation = p.object("animation");
    target.animation = ParseAnimation(animation);
  }

  const json& objects = p.raw("objects");
  Location objects_at = p.where("objects");
  if (!objects.is_array()) p.fail("objects", "expected an array of objects, got " + JsonKindName(objects));
  if (objects.empty()) p.fail("objects", "no objects: the light field would show only the background");
  if (objects.size() > kMaxObjects)
    p.fail("objects", std::to_string(objects.size()) + " objects; the limit is " + std::to_string(kMaxObjects));
  std::vector<std::string> parts;
  if (!description.empty()) parts.push_back(description);
  for (size_t i = 0; i < objects.size(); ++i) {
    Params o(objects[i], objects_at.child(i));
    o.string("type");  // required
    std::string type = o.choice("type", {"plane", "mesh"}, "");
    std::string what;
    if (type == "plane")
      target.planes.push_back(ParsePlane(o, target.geometry, base_dir, what, target.files_read));
    else
      target.meshes.push_back(ParseMesh(o, base_dir, what, target.files_read));
    parts.push_back(what);
  }
  p.check_all_read();
  if (!target.animation &&
      std::any_of(target.meshes.begin(), target.meshes.end(), [](const TargetMesh& m) { return m.motion != nullptr; }))
    target.animation.emplace();  // keys alone: the default frame rate
  if (target.animation) target = Posed(target, {0, 0, 0}, 0.0);
  for (size_t i = 0; i < parts.size(); ++i) target.description += (i ? "; " : "") + parts[i];
  return target;
}

TargetScene LoadTarget(const std::string& path, const SceneReader& read_scene) {
  FileBytes bytes;
  TargetScene target = ParseTarget(ReadJsonFile(path, {}, &bytes), path, read_scene);
  target.file_bytes = bytes;
  return target;
}

void MoveTargetScene(TargetScene* scene, const std::array<double, 3>& moved_m) {
  const std::array<double, 3> by = {moved_m[0] - scene->moved_m[0], moved_m[1] - scene->moved_m[1],
                                    moved_m[2] - scene->moved_m[2]};
  for (TargetPlane& plane : scene->planes) {
    plane.center_m[0] += by[0], plane.center_m[1] += by[1];
    plane.depth_m += by[2];
  }
  for (TargetMesh& mesh : scene->meshes)
    for (std::array<double, 3>& p : mesh.mesh.positions)
      for (int k = 0; k < 3; ++k) p[k] += by[k];
  scene->moved_m = moved_m;
}

}  // namespace layerlab
