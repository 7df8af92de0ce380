#include "systems/target/target_renderer.h"

#include <atomic>
#include <chrono>
#include <cmath>

#include <tbb/parallel_for.h>

#include "systems/target/embree_scene.h"
#include "systems/target/pixel_sampling.h"

namespace layerlab {
namespace {

using Vec3 = std::array<double, 3>;

Vec3 Sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double Dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3 Cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

// What an Embree geometry id stands for.
struct Surface {
  bool is_plane = true;
  size_t index = 0;  // into target.planes or target.meshes
};

struct Sample {
  Rgb color;
  double z;  // eye-space depth of the hit, or +inf
};

class Tracer {
 public:
  explicit Tracer(const TargetScene& target) : target_(target) {
    for (size_t i = 0; i < target.planes.size(); ++i) {
      const TargetPlane& p = target.planes[i];
      double x0 = p.center[0] - p.size[0] / 2, x1 = p.center[0] + p.size[0] / 2;
      double y0 = p.center[1] - p.size[1] / 2, y1 = p.center[1] + p.size[1] / 2;
      std::array<std::array<double, 3>, 4> corners{{{x0, y0, p.depth}, {x1, y0, p.depth}, {x1, y1, p.depth},
                                                    {x0, y1, p.depth}}};
      std::array<std::array<uint32_t, 3>, 2> triangles{{{0, 1, 2}, {0, 2, 3}}};
      Register(scene_.AddTriangles(target.file + ": plane " + std::to_string(i), corners, triangles),
               {true, i});
    }
    for (size_t i = 0; i < target.meshes.size(); ++i) {
      const TriangleMesh& m = target.meshes[i].mesh;
      Register(scene_.AddTriangles(target.meshes[i].file, m.positions, m.triangles), {false, i});
    }
    scene_.Commit();
  }

  // The ray from (vx, vy, 0) through (x, y, z_lf).
  Sample Trace(double vx, double vy, double x, double y) const {
    const double z_lf = target_.geometry.origin_z;
    // Direction with unit z: the ray parameter is the eye-space depth.
    Vec3 origin{vx, vy, 0}, direction{(x - vx) / z_lf, (y - vy) / z_lf, 1.0};
    RayHit hit = scene_.Intersect({static_cast<float>(vx), static_cast<float>(vy), 0.0f},
                                  {static_cast<float>(direction[0]), static_cast<float>(direction[1]), 1.0f});
    if (!hit.hit()) return {target_.background, INFINITY};
    const Surface& surface = surfaces_[hit.geom_id];
    if (surface.is_plane) {
      const TargetPlane& plane = target_.planes[surface.index];
      double z = plane.depth;
      return {plane.texture->Evaluate(vx + direction[0] * z - plane.center[0], vy + direction[1] * z - plane.center[1]),
              z};
    }
    const TargetMesh& mesh = target_.meshes[surface.index];
    const auto& tri = mesh.mesh.triangles[hit.prim_id];
    const Vec3 &p0 = mesh.mesh.positions[tri[0]], &p1 = mesh.mesh.positions[tri[1]], &p2 = mesh.mesh.positions[tri[2]];
    Vec3 n = Cross(Sub(p1, p0), Sub(p2, p0));
    double n_dot_d = Dot(n, direction);
    double z = n_dot_d != 0 ? Dot(n, Sub(p0, origin)) / n_dot_d : hit.t;
    if (!std::isfinite(z) || std::abs(z - hit.t) > 1e-3 * hit.t) z = hit.t;  // grazing: keep Embree's
    double length = std::sqrt(Dot(n, n));
    double lambert = 0;
    if (length > 0) {
      if (n_dot_d > 0) length = -length;  // face the viewer
      lambert = std::max(0.0, Dot(n, target_.light.to_light) / length);
    }
    double shade = target_.light.ambient + (1 - target_.light.ambient) * lambert;
    double s = 0, t = 0;
    if (mesh.mesh.has_uvs()) {
      const auto& tuv = mesh.mesh.triangle_uvs[hit.prim_id];
      double w0 = 1.0 - hit.u - hit.v;
      for (int k = 0; k < 2; ++k) {
        double uv = w0 * mesh.mesh.uvs[tuv[0]][k] + hit.u * mesh.mesh.uvs[tuv[1]][k] + hit.v * mesh.mesh.uvs[tuv[2]][k];
        (k == 0 ? s : t) = (uv - 0.5) * mesh.uv_size;
      }
    }
    Rgb c = mesh.texture->Evaluate(s, t);
    return {{c[0] * shade, c[1] * shade, c[2] * shade}, z};
  }

 private:
  void Register(unsigned id, Surface surface) {
    if (id >= surfaces_.size()) surfaces_.resize(id + 1);
    surfaces_[id] = surface;
  }

  const TargetScene& target_;
  EmbreeScene scene_;
  std::vector<Surface> surfaces_;
};

}  // namespace

LightField RenderTarget(const TargetScene& target, RenderStats* stats, const RenderProgress& progress) {
  auto start = std::chrono::steady_clock::now();
  const LightFieldGeometry& g = target.geometry;
  Tracer tracer(target);
  LightField lf(g);
  lf.scene = target.description;
  lf.depth.assign(g.ray_count(), kBackgroundDepth);
  const PixelSampler sampler(g, target.samples_per_pixel, target.seed);
  const int n = sampler.samples();
  std::atomic<uint64_t> rays{0};
  std::atomic<size_t> views_done{0};

  tbb::parallel_for(size_t{0}, g.view_count(), [&](size_t view) {
    const double vx = g.view_x(static_cast<int>(view % g.views_x));
    const double vy = g.view_y(static_cast<int>(view / g.views_x));
    float* rgb = lf.view(view);
    float* depth = lf.depth.data() + view * g.pixels_per_view();
    uint64_t view_rays = 0;
    for (int i = 0; i < g.rows; ++i)
      for (int j = 0; j < g.cols; ++j) {
        double sum[3] = {0, 0, 0};
        for (int k = 0; k < n; ++k) {
          auto [x, y] = sampler.Sample(i, j, k);
          Sample s = tracer.Trace(vx, vy, x, y);
          for (int ch = 0; ch < 3; ++ch) sum[ch] += s.color[ch];
          if (n == 1 && std::isfinite(s.z)) depth[static_cast<size_t>(i) * g.cols + j] = static_cast<float>(s.z);
        }
        view_rays += n;
        if (n > 1) {
          Sample center = tracer.Trace(vx, vy, g.pixel_x(j), g.pixel_y(i));
          if (std::isfinite(center.z)) depth[static_cast<size_t>(i) * g.cols + j] = static_cast<float>(center.z);
          ++view_rays;
        }
        size_t p = (static_cast<size_t>(i) * g.cols + j) * 3;
        for (int ch = 0; ch < 3; ++ch) rgb[p + ch] = static_cast<float>(sum[ch] / n);
      }
    rays += view_rays;
    size_t done = ++views_done;
    if (progress) progress(done, g.view_count());
  });

  if (stats) {
    stats->rays = rays;
    stats->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  return lf;
}

}  // namespace layerlab
