// What the eye should see, for the commands that compare the display with
// its target through an eye (retina, eyebox): natural viewing of the target
// given on the command line, a light field read as the layers are, or a
// target scene traced ray by ray (from any pupil).
#pragma once

#include <memory>
#include <optional>

#include "layerlab/framework/lightfield.h"
#include "layerlab/retina/scene_radiance.h"
#include "layerlab/solvers/solve_config.h"

namespace layerlab {
struct TargetScene;
class TargetTracer;
}  // namespace layerlab

namespace layerlab::app {

class NaturalViewing {
 public:
  // `given` holds --target or --target-scene (ApplyTargetOption), or neither.
  NaturalViewing(const SolveConfig& given, Sampling sampling);
  ~NaturalViewing();
  NaturalViewing(const NaturalViewing&) = delete;
  NaturalViewing& operator=(const NaturalViewing&) = delete;

  // Empty without a target.
  const SceneRadiance& radiance() const { return radiance_; }
  // The light field's, or nullptr for a traced target or none.
  const LightField* light_field() const { return light_field_ ? &*light_field_ : nullptr; }

 private:
  std::optional<LightField> light_field_;
  std::shared_ptr<const TargetScene> scene_;  // shared: the types are complete only with Embree
  std::shared_ptr<TargetTracer> tracer_;
  SceneRadiance radiance_;
};

}  // namespace layerlab::app
