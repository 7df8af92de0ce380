#include "layerlab/targets/target_tracer.h"

#include <algorithm>
#include <cmath>

namespace layerlab {
namespace {

using Vec3 = std::array<double, 3>;

Vec3 Sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double Dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3 Cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

// A mesh hit's triangle: its first vertex and its geometric normal (p1 - p0) x (p2 - p0).
struct HitTriangle {
  Vec3 p0, n;
};

HitTriangle TriangleOf(const TargetMesh& mesh, const RayHit& hit) {
  const auto& tri = mesh.mesh.triangles[hit.prim_id];
  const Vec3 &p0 = mesh.mesh.positions[tri[0]], &p1 = mesh.mesh.positions[tri[1]], &p2 = mesh.mesh.positions[tri[2]];
  return {p0, Cross(Sub(p1, p0), Sub(p2, p0))};
}

// The hit's depth refined in double precision on its triangle's plane; the ray's direction has unit z, so its
// parameter is the eye-space depth. A grazing ray keeps Embree's.
double RefinedDepth(const HitTriangle& tri, const Vec3& origin, const Vec3& direction, float hit_t) {
  const double n_dot_d = Dot(tri.n, direction);
  double z = n_dot_d != 0 ? Dot(tri.n, Sub(tri.p0, origin)) / n_dot_d : hit_t;
  if (!std::isfinite(z) || std::abs(z - hit_t) > 1e-3 * hit_t) z = hit_t;
  return z;
}

}  // namespace

TargetTracer::TargetTracer(const TargetScene& target) : target_(target) {
  for (size_t i = 0; i < target.planes.size(); ++i) {
    const TargetPlane& p = target.planes[i];
    double x0 = p.center_m[0] - p.size_m[0] / 2, x1 = p.center_m[0] + p.size_m[0] / 2;
    double y0 = p.center_m[1] - p.size_m[1] / 2, y1 = p.center_m[1] + p.size_m[1] / 2;
    std::array<std::array<double, 3>, 4> corners{
        {{x0, y0, p.depth_m}, {x1, y0, p.depth_m}, {x1, y1, p.depth_m}, {x0, y1, p.depth_m}}};
    std::array<std::array<uint32_t, 3>, 2> triangles{{{0, 1, 2}, {0, 2, 3}}};
    Register(scene_.AddTriangles(target.file + ": plane " + std::to_string(i), corners, triangles), {true, i});
  }
  for (size_t i = 0; i < target.meshes.size(); ++i) {
    const TriangleMesh& m = target.meshes[i].mesh;
    Register(scene_.AddTriangles(target.meshes[i].file, m.positions, m.triangles), {false, i});
  }
  scene_.Commit();
}

TracedSample TargetTracer::TraceDirection(double vx, double vy, double dx, double dy) const {
  RayHit hit = scene_.Intersect({static_cast<float>(vx), static_cast<float>(vy), 0.0f},
                                {static_cast<float>(dx), static_cast<float>(dy), 1.0f});
  return Shade(hit, vx, vy, dx, dy);
}

void TargetTracer::IntersectFrom(double vx, double vy, std::span<const std::array<double, 2>> slopes,
                                 std::span<RayHit> hits) const {
  thread_local std::vector<std::array<float, 3>> directions;
  directions.resize(slopes.size());
  for (size_t i = 0; i < slopes.size(); ++i)
    directions[i] = {static_cast<float>(slopes[i][0]), static_cast<float>(slopes[i][1]), 1.0f};
  scene_.IntersectFrom({static_cast<float>(vx), static_cast<float>(vy), 0.0f}, directions, hits);
}

double TargetTracer::Depth(const RayHit& hit, double vx, double vy, double dx, double dy) const {
  if (!hit.hit()) return INFINITY;
  const Surface& surface = surfaces_[hit.geom_id];
  if (surface.is_plane) return target_.planes[surface.index].depth_m;
  return RefinedDepth(TriangleOf(target_.meshes[surface.index], hit), {vx, vy, 0}, {dx, dy, 1.0}, hit.t);
}

TracedSample TargetTracer::Shade(const RayHit& hit, double vx, double vy, double dx, double dy) const {
  if (!hit.hit()) return {target_.background, INFINITY};
  const Surface& surface = surfaces_[hit.geom_id];
  if (surface.is_plane) {
    const TargetPlane& plane = target_.planes[surface.index];
    double z = plane.depth_m;
    return {plane.texture->Evaluate(vx + dx * z - plane.center_m[0], vy + dy * z - plane.center_m[1]), z};
  }
  const Vec3 direction{dx, dy, 1.0};
  const TargetMesh& mesh = target_.meshes[surface.index];
  const HitTriangle tri = TriangleOf(mesh, hit);
  const Vec3& n = tri.n;
  const double z = RefinedDepth(tri, {vx, vy, 0}, direction, hit.t);
  double length = std::sqrt(Dot(n, n));
  double lambert = 0;
  if (length > 0) {
    if (Dot(n, direction) > 0) length = -length;  // face the viewer
    lambert = std::max(0.0, Dot(n, target_.light.to_light) / length);
  }
  double shade = target_.light.ambient + (1 - target_.light.ambient) * lambert;
  double s = 0, t = 0;
  if (mesh.mesh.has_uvs()) {
    const auto& tuv = mesh.mesh.triangle_uvs[hit.prim_id];
    double w0 = 1.0 - hit.u - hit.v;
    for (int k = 0; k < 2; ++k) {
      double uv = w0 * mesh.mesh.uvs[tuv[0]][k] + hit.u * mesh.mesh.uvs[tuv[1]][k] + hit.v * mesh.mesh.uvs[tuv[2]][k];
      (k == 0 ? s : t) = (uv - 0.5) * mesh.uv_size_m;
    }
  }
  Rgb c = mesh.texture->Evaluate(s, t);
  return {{c[0] * shade, c[1] * shade, c[2] * shade}, z};
}

void TargetTracer::Register(unsigned id, Surface surface) {
  if (id >= surfaces_.size()) surfaces_.resize(id + 1);
  surfaces_[id] = surface;
}

}  // namespace layerlab
