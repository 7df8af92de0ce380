// Embree 3, wrapped once, in the order of its minimal tutorial: device ->
// error callback -> scene -> geometry buffers -> commit -> attach ->
// intersect -> release. Only embree_scene.cpp includes <embree3/rtcore.h>.
//
// Embree is handed nothing it cannot take: Debian's build aborts on a NaN or
// infinite ray (its assertions are on) and silently never hits a triangle
// with a NaN vertex, so vertices and rays are checked here first and refused
// as layerlab::Error. Embree's own errors arrive through its error callback
// and are rethrown as layerlab::Error after the call that raised them.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <string>

namespace layerlab {

inline constexpr unsigned kNoGeometry = 0xFFFFFFFFu;  // RTC_INVALID_GEOMETRY_ID

struct RayHit {
  float t = std::numeric_limits<float>::infinity();  // ray parameter of the closest hit
  unsigned geom_id = kNoGeometry;                    // as returned by AddTriangles
  unsigned prim_id = kNoGeometry;                    // triangle index within that geometry
  float u = 0, v = 0;                                // barycentrics: p = (1 - u - v) p0 + u p1 + v p2
  std::array<float, 3> normal{};                     // geometric normal (p1 - p0) x (p2 - p0), not normalized

  bool hit() const { return geom_id != kNoGeometry; }
};

class EmbreeScene {
 public:
  EmbreeScene();  // a device with its error callback, and an empty scene
  ~EmbreeScene();
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  // Adds one triangle mesh before Commit(); `name` (the mesh file) labels errors.
  // Refuses a vertex that is not finite in single precision and an index out
  // of range, naming the vertex or triangle. Returns the geometry id hits report.
  unsigned AddTriangles(const std::string& name, std::span<const std::array<double, 3>> vertices,
                        std::span<const std::array<uint32_t, 3>> triangles);
  // Builds the acceleration structure; after it, only Intersect.
  void Commit();

  // Closest hit along origin + t * direction for t in [t_near, t_far]; safe to
  // call from many threads. Refuses a non-finite ray or a zero direction.
  RayHit Intersect(const std::array<float, 3>& origin, const std::array<float, 3>& direction, float t_near = 0.0f,
                   float t_far = std::numeric_limits<float>::infinity()) const;
  // The closest hits (t >= 0) of many rays from one origin, ray i along directions[i], traced together as
  // one coherent stream (rays that share an origin and point in nearby directions traverse together).
  // Refuses a non-finite ray or a zero direction. `hits` has as many entries as `directions`.
  void IntersectFrom(const std::array<float, 3>& origin, std::span<const std::array<float, 3>> directions,
                     std::span<RayHit> hits) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace layerlab
