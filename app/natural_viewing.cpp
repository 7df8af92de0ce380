#include "layerlab/app/natural_viewing.h"

#include "layerlab/framework/lightfield_io.h"
#include "layerlab/retina/lightfield_radiance.h"
#if LAYERLAB_WITH_EMBREE
#include "layerlab/targets/target_scene.h"
#include "layerlab/targets/target_tracer.h"
#endif

namespace layerlab::app {

NaturalViewing::NaturalViewing(const SolveConfig& given, Sampling sampling) {
  if (!given.target.empty()) {
    light_field_ = ReadLightField(given.target, {.load_depth = false});
    radiance_ = LightFieldRadiance(*light_field_, sampling);  // read as the layers are
  }
#if LAYERLAB_WITH_EMBREE
  if (!given.target_scene.empty()) {
    auto scene = std::make_shared<TargetScene>(LoadTarget(given.target_scene));
    MoveTargetScene(scene.get(), given.target_moved_m);
    scene_ = scene;
    tracer_ = std::make_shared<TargetTracer>(*scene_);
    TargetTracer* tracer = tracer_.get();
    radiance_ = [tracer](const PupilPoint& u, double dx, double dy) {
      return tracer->TraceDirection(u.x_m, u.y_m, dx, dy).color;
    };
  }
#endif
}

NaturalViewing::~NaturalViewing() = default;

}  // namespace layerlab::app
