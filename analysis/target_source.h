// The target of a run: a light-field folder read from disk, or a target scene
// (docs/target-format.md) rendered with Embree. A rendered target keeps its
// ray tracer, so that natural viewing on the retina is traced exactly rather
// than interpolated from the views.
#pragma once

#include <array>
#include <memory>
#include <string>

#include "layerlab/framework/lightfield.h"
#include "layerlab/retina/retina.h"
#include "layerlab/solvers/solve_config.h"
#if LAYERLAB_WITH_EMBREE
#include "layerlab/targets/target_renderer.h"
#include "layerlab/targets/target_scene.h"
#include "layerlab/targets/target_tracer.h"
#endif

namespace layerlab {

struct Target {
  LightField light_field;
  std::string source;  // the folder or the target scene file
  bool rendered = false;
  std::string digest;               // a target scene's: TargetSceneDigest (analysis/target_cache.h)
  bool reused = false;              // its render was read from the cache
  std::array<double, 3> moved_m{};  // where its scene was moved to (SolveConfig::target_moved_m); 0 for a folder
#if LAYERLAB_WITH_EMBREE
  std::unique_ptr<TargetScene> scene;  // stable address: the tracer refers to it
  std::unique_ptr<TargetTracer> tracer;
#endif
  // Radiance along any ray from the pupil, for natural viewing. kLightField
  // reads the target light field: the very rays the display is asked to
  // reproduce, so display and natural viewing are compared like for like,
  // image-wise in milliseconds per retinal image. kTraced traces a rendered
  // target's scene exactly (detail finer than the views), ray by ray, seconds
  // per image; a target read from a folder has only its light field.
  enum class Viewing { kLightField, kTraced };
  SceneRadiance Natural(Viewing how = Viewing::kLightField) const;
  bool traceable() const;  // rendered from a scene whose tracer it keeps
};

// With the solve's retinal_target "traced" (RetinalTarget::kTraced): the
// retinal objective's target images traced from this target's scene, which
// must then outlive the solve. Throws layerlab::Error naming the key when the
// target is a light-field folder. Otherwise leaves `options` as they are.
void AttachRetinalTarget(const Target& target, SolverOptions* options);

// Where a run keeps the render of its target scene (analysis/target_cache.h).
struct RenderCache {
  std::string previous;  // may hold an earlier render (a run's committed OUT/target)
  std::string next;      // this run's render goes here (the staging folder's target/)
  std::string shared;    // a store of renders by key shared by several runs (a sweep's DIR/targets), or ""
};

// Reads config.target, or renders config.target_scene with a progress bar of
// views; with `cache`, a render of the same scene in cache->previous (then in
// cache->shared) is read instead, and the render is kept in cache->next (and
// a new one in cache->shared). Says on stderr which.
// Throws layerlab::Error when neither is given or the scene needs Embree and
// this build has none.
std::unique_ptr<Target> LoadOrRenderTarget(const SolveConfig& config, const std::string& label,
                                           const RenderCache* cache = nullptr);
#if LAYERLAB_WITH_EMBREE
// The same with config.target_scene already read into `scene` (null: read it here), so that a run reads it once.
std::unique_ptr<Target> LoadOrRenderTarget(const SolveConfig& config, const std::string& label,
                                           const RenderCache* cache, std::unique_ptr<TargetScene> scene);
#endif

// What the target is, for reports: "rendered from T.json (key ..., reused
// from the cache): 13 x 13 views of 400 x 200 pixels" or "light field DIR: ...".
std::string DescribeTarget(const Target& target);

// The target's geometry without reading its views or rendering it: the
// light field's manifest, or the target scene's declared geometry.
LightFieldGeometry TargetGeometry(const SolveConfig& config);

// Refuses (layerlab::Error with the estimate and its parts) a solve of
// `config` estimated to need more than `limit` bytes; `limit_name` says
// where the limit came from ("--max-memory 200.0 MB"). A limit of 0: the
// machine's memory. Returns the estimate. Reads no views, renders nothing.
size_t RefuseSolveBeyondMemory(const DisplaySystem& system, const SolveConfig& config, int threads, size_t limit = 0,
                               const std::string& limit_name = "");
// The same for the rays of `geometry` (one MPI rank's block of views).
size_t RefuseSolveBeyondMemory(const DisplaySystem& system, const LightFieldGeometry& geometry,
                               const SolveConfig& config, int threads, size_t limit, const std::string& limit_name);

// The center view as an sRGB PNG (1 = white), to show what the target looks
// like, reduced to the report's preview width (framework/shown_image.h);
// returns its width and height.
std::array<int, 2> WriteCenterView(const LightField& lf, const std::string& path);

}  // namespace layerlab
