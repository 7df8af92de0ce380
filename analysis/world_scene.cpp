#include "layerlab/analysis/world_scene.h"

#include <memory>
#include <vector>

#include "layerlab/framework/error.h"
#if LAYERLAB_WITH_EMBREE
#include "layerlab/targets/target_scene.h"
#include "layerlab/targets/target_tracer.h"
#endif

namespace layerlab {

SceneRadiance WorldSceneRadiance(const DisplaySystem& system) {
  bool any = false;
  for (const WorldView& w : system.worlds) any = any || !w.scene_file.empty();
  if (!any) return {};
#if LAYERLAB_WITH_EMBREE
  struct Traced {
    Rgb scale;              // cd/m^2 at the eye per unit of radiance
    double sx = 1, sy = 1;  // -1 along an axis its path mirrors: the ray's x (y) in the world's own frame
    std::shared_ptr<const TargetScene> scene;
    std::shared_ptr<const TargetTracer> tracer;  // refers to *scene
  };
  auto worlds = std::make_shared<std::vector<Traced>>();
  for (const WorldView& w : system.worlds) {
    Traced t;
    for (int c = 0; c < 3; ++c) t.scale[c] = w.luminance_cd_m2 * w.efficiency[c];
    t.sx = w.flip_x ? -1 : 1, t.sy = w.flip_y ? -1 : 1;
    if (!w.scene_file.empty()) {
      t.scene = std::make_shared<const TargetScene>(LoadTarget(w.scene_file));
      t.tracer = std::make_shared<const TargetTracer>(*t.scene);
    }
    worlds->push_back(std::move(t));
  }
  return [worlds](const PupilPoint& u, double dx, double dy) {
    std::array<double, 3> sum{};
    for (const Traced& t : *worlds) {
      std::array<double, 3> radiance = {1, 1, 1};
      if (t.tracer) radiance = t.tracer->TraceDirection(t.sx * u.x_m, t.sy * u.y_m, t.sx * dx, t.sy * dy).color;
      for (int c = 0; c < 3; ++c) sum[c] += t.scale[c] * radiance[c];
    }
    return sum;
  };
#else
  throw Error(
      "a world with a \"scene\" is traced with Embree, which this build has none of (LAYERLAB_WITH_EMBREE=OFF)");
#endif
}

}  // namespace layerlab
