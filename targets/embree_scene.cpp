#include "layerlab/targets/embree_scene.h"

#include <cmath>
#include <mutex>
#include <sstream>
#include <vector>

#include <embree3/rtcore.h>

#include "layerlab/framework/error.h"

namespace layerlab {
namespace {

struct DeviceDeleter {
  void operator()(RTCDeviceTy* d) const { rtcReleaseDevice(d); }
};
struct SceneDeleter {
  void operator()(RTCSceneTy* s) const { rtcReleaseScene(s); }
};
struct GeometryDeleter {
  void operator()(RTCGeometryTy* g) const { rtcReleaseGeometry(g); }
};

const char* ErrorCodeName(RTCError code) {
  switch (code) {
    case RTC_ERROR_NONE:
      return "no error";
    case RTC_ERROR_INVALID_ARGUMENT:
      return "invalid argument";
    case RTC_ERROR_INVALID_OPERATION:
      return "invalid operation";
    case RTC_ERROR_OUT_OF_MEMORY:
      return "out of memory";
    case RTC_ERROR_UNSUPPORTED_CPU:
      return "unsupported CPU";
    case RTC_ERROR_CANCELLED:
      return "cancelled";
    default:
      return "unknown error";
  }
}

std::string Number(double x) {
  std::ostringstream out;
  out << x;
  return out.str();
}

std::string Triple(double x, double y, double z) { return "(" + Number(x) + ", " + Number(y) + ", " + Number(z) + ")"; }

[[noreturn]] void RefuseRay(const std::array<float, 3>& origin, const std::array<float, 3>& direction, float t_near,
                            float t_far) {
  throw Error("Embree: internal error: refusing to trace the ray from " + Triple(origin[0], origin[1], origin[2]) +
              " along " + Triple(direction[0], direction[1], direction[2]) + " for t in [" + Number(t_near) + ", " +
              Number(t_far) + "]");
}

inline void RequireTraceable(const std::array<float, 3>& origin, const std::array<float, 3>& direction, float t_near,
                             float t_far) {
  const bool finite = std::isfinite(origin[0]) && std::isfinite(origin[1]) && std::isfinite(origin[2]) &&
                      std::isfinite(direction[0]) && std::isfinite(direction[1]) && std::isfinite(direction[2]) &&
                      std::isfinite(t_near) && !std::isnan(t_far);
  const bool nonzero = direction[0] != 0 || direction[1] != 0 || direction[2] != 0;
  if (!finite || !nonzero || !(t_near >= 0) || !(t_far >= t_near)) [[unlikely]]
    RefuseRay(origin, direction, t_near, t_far);
}

void SetQuery(const std::array<float, 3>& origin, const std::array<float, 3>& direction, float t_near, float t_far,
              RTCRayHit* query) {
  query->ray.org_x = origin[0];
  query->ray.org_y = origin[1];
  query->ray.org_z = origin[2];
  query->ray.dir_x = direction[0];
  query->ray.dir_y = direction[1];
  query->ray.dir_z = direction[2];
  query->ray.tnear = t_near;
  query->ray.tfar = t_far;
  query->ray.time = 0.0f;
  query->ray.mask = 0xFFFFFFFFu;
  query->ray.id = 0;
  query->ray.flags = 0;
  query->hit.geomID = RTC_INVALID_GEOMETRY_ID;
  query->hit.primID = RTC_INVALID_GEOMETRY_ID;
  query->hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
}

RayHit HitOf(const RTCRayHit& query) {
  RayHit hit;
  if (query.hit.geomID == RTC_INVALID_GEOMETRY_ID) return hit;
  hit.t = query.ray.tfar;
  hit.geom_id = query.hit.geomID;
  hit.prim_id = query.hit.primID;
  hit.u = query.hit.u;
  hit.v = query.hit.v;
  hit.normal = {query.hit.Ng_x, query.hit.Ng_y, query.hit.Ng_z};
  return hit;
}

}  // namespace

struct EmbreeScene::Impl {
  // The callback runs on the thread of the failing call; the message waits
  // here until that call returns and ThrowIfFailed turns it into an Error.
  std::mutex error_mutex;
  std::string error;

  std::unique_ptr<RTCDeviceTy, DeviceDeleter> device;  // released last: declared first
  std::unique_ptr<RTCSceneTy, SceneDeleter> scene;
  bool committed = false;

  static void OnError(void* user, RTCError code, const char* message) {
    auto* self = static_cast<Impl*>(user);
    std::lock_guard<std::mutex> lock(self->error_mutex);
    if (self->error.empty())
      self->error = std::string(ErrorCodeName(code)) + (message ? std::string(": ") + message : "");
  }

  void ThrowIfFailed(const std::string& call) {
    std::lock_guard<std::mutex> lock(error_mutex);
    if (error.empty()) return;
    std::string message = "Embree: " + call + " failed: " + error;
    error.clear();
    throw Error(message);
  }
};

EmbreeScene::EmbreeScene() : impl_(std::make_unique<Impl>()) {
  impl_->device.reset(rtcNewDevice(nullptr));
  if (!impl_->device)
    throw Error(std::string("Embree: cannot create a device: ") + ErrorCodeName(rtcGetDeviceError(nullptr)));
  rtcSetDeviceErrorFunction(impl_->device.get(), &Impl::OnError, impl_.get());
  impl_->scene.reset(rtcNewScene(impl_->device.get()));
  impl_->ThrowIfFailed("rtcNewScene");
  // Robust traversal keeps rays through a shared edge from slipping between two triangles.
  rtcSetSceneFlags(impl_->scene.get(), RTC_SCENE_FLAG_ROBUST);
  impl_->ThrowIfFailed("rtcSetSceneFlags");
}

EmbreeScene::~EmbreeScene() = default;

unsigned EmbreeScene::AddTriangles(const std::string& name, std::span<const std::array<double, 3>> vertices,
                                   std::span<const std::array<uint32_t, 3>> triangles) {
  if (impl_->committed) throw Error(name + ": internal error: geometry added after the scene was committed");
  if (vertices.empty() || triangles.empty()) throw Error(name + ": the mesh has no triangles");
  std::vector<float> converted(vertices.size() * 3);
  for (size_t i = 0; i < vertices.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      float c = static_cast<float>(vertices[i][k]);
      if (!std::isfinite(c))
        throw Error(name + ": vertex " + std::to_string(i) + " is " +
                    Triple(vertices[i][0], vertices[i][1], vertices[i][2]) +
                    " after placement; every coordinate must be finite (in single precision)");
      converted[i * 3 + k] = c;
    }
  for (size_t t = 0; t < triangles.size(); ++t)
    for (uint32_t index : triangles[t])
      if (index >= vertices.size())
        throw Error(name + ": triangle " + std::to_string(t) + " uses vertex " + std::to_string(index) +
                    ", beyond the " + std::to_string(vertices.size()) + " vertices");

  std::unique_ptr<RTCGeometryTy, GeometryDeleter> geometry(
      rtcNewGeometry(impl_->device.get(), RTC_GEOMETRY_TYPE_TRIANGLE));
  impl_->ThrowIfFailed("rtcNewGeometry for " + name);
  auto* vertex_buffer = static_cast<float*>(rtcSetNewGeometryBuffer(
      geometry.get(), RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), vertices.size()));
  impl_->ThrowIfFailed("rtcSetNewGeometryBuffer (vertices of " + name + ")");
  auto* index_buffer = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(
      geometry.get(), RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(uint32_t), triangles.size()));
  impl_->ThrowIfFailed("rtcSetNewGeometryBuffer (triangles of " + name + ")");
  if (!vertex_buffer || !index_buffer) throw Error("Embree: no buffer for " + name);
  std::copy(converted.begin(), converted.end(), vertex_buffer);
  for (size_t t = 0; t < triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) index_buffer[t * 3 + k] = triangles[t][k];
  rtcCommitGeometry(geometry.get());
  impl_->ThrowIfFailed("rtcCommitGeometry for " + name);
  unsigned id = rtcAttachGeometry(impl_->scene.get(), geometry.get());
  impl_->ThrowIfFailed("rtcAttachGeometry for " + name);
  return id;  // the scene holds its own reference; ours is released here
}

void EmbreeScene::Commit() {
  rtcCommitScene(impl_->scene.get());
  impl_->ThrowIfFailed("rtcCommitScene");
  impl_->committed = true;
}

RayHit EmbreeScene::Intersect(const std::array<float, 3>& origin, const std::array<float, 3>& direction, float t_near,
                              float t_far) const {
  if (!impl_->committed) throw Error("Embree: internal error: intersect before the scene was committed");
  RequireTraceable(origin, direction, t_near, t_far);
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit query;
  SetQuery(origin, direction, t_near, t_far, &query);
  rtcIntersect1(impl_->scene.get(), &context, &query);
  return HitOf(query);
}

void EmbreeScene::IntersectFrom(const std::array<float, 3>& origin, std::span<const std::array<float, 3>> directions,
                                std::span<RayHit> hits) const {
  if (!impl_->committed) throw Error("Embree: internal error: intersect before the scene was committed");
  if (hits.size() != directions.size()) throw Error("Embree: internal error: hits and directions differ in count");
  thread_local std::vector<RTCRayHit> queries;
  queries.resize(directions.size());
  for (size_t i = 0; i < directions.size(); ++i) {
    RequireTraceable(origin, directions[i], 0.0f, std::numeric_limits<float>::infinity());
    SetQuery(origin, directions[i], 0.0f, std::numeric_limits<float>::infinity(), &queries[i]);
  }
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  rtcIntersect1M(impl_->scene.get(), &context, queries.data(), static_cast<unsigned>(queries.size()),
                 sizeof(RTCRayHit));
  for (size_t i = 0; i < queries.size(); ++i) hits[i] = HitOf(queries[i]);
}

}  // namespace layerlab
