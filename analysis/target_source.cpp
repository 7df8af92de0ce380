#include "layerlab/analysis/target_source.h"

#include <omp.h>

#include <cstdio>
#include <optional>

#include "layerlab/analysis/target_cache.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/lightfield_io.h"
#include "layerlab/framework/progress.h"
#include "layerlab/framework/shown_image.h"
#include "layerlab/framework/warnings.h"
#include "layerlab/retina/lightfield_radiance.h"
#include "layerlab/solvers/memory_estimate.h"
#include "layerlab/targets/target_scene.h"

namespace layerlab {

SceneRadiance Target::Natural(Viewing how) const {
#if LAYERLAB_WITH_EMBREE
  if (how == Viewing::kTraced && tracer) {
    const TargetTracer* t = tracer.get();
    return [t](const PupilPoint& u, double dx, double dy) { return t->TraceDirection(u.x_m, u.y_m, dx, dy).color; };
  }
#else
  (void)how;
#endif
  return LightFieldRadiance(light_field);
}

bool Target::traceable() const {
#if LAYERLAB_WITH_EMBREE
  return tracer != nullptr;
#else
  return false;
#endif
}

void AttachRetinalTarget(const Target& target, SolverOptions* options) {
  if (options->retinal.target != RetinalTarget::kTraced) return;
  if (!target.traceable())
    throw Error("retinal_target \"traced\": the target " + target.source +
                " is a light field, and tracing needs the target scene itself (target_scene, or --target-scene)");
  options->retinal.target_radiance = target.Natural(Target::Viewing::kTraced);
  Note("retinal objective: the target's retinal images traced from " + target.source + ", ray by ray");
}

#if LAYERLAB_WITH_EMBREE
namespace {

void Render(const std::string& label, Target* target) {
  const LightFieldGeometry& g = target->scene->geometry;
  Progress progress(label, size_t(g.rows));
  char what[160];
  std::snprintf(what, sizeof what, "%d x %d pixels", g.cols, g.rows);
  RenderStats stats;
  target->light_field = RenderTarget(*target->scene, &stats, [&](size_t done, size_t total) {
    progress.Update(done, std::string("pixel rows rendered in every view, ") + what);
  });
  std::snprintf(what, sizeof what, "%zu views of %d x %d pixels, %.1f Mrays/s", g.view_count(), g.cols, g.rows,
                stats.rays / std::max(stats.seconds, 1e-9) / 1e6);
  progress.Finish(what);
}

// The target's light field from the run's earlier render, else from the shared store (waiting for a
// process that renders it now), else rendered; kept in cache->next, and put in the store when rendered.
void ReadOrRender(const std::string& scene_file, const std::string& label, const RenderCache* cache, Target* target) {
  if (!cache) return Render(label, target);
  const std::string& digest = target->digest;
  std::string why_not, reuse_from;
  auto reuse = [&](const std::string& folder, const std::string& whose) {
    std::optional<LightField> cached = ReadCachedRender(folder, digest, &why_not);
    if (!cached) return false;
    target->light_field = std::move(*cached);
    target->reused = true;
    reuse_from = folder;
    Note(label + ": reusing the render of " + scene_file + " in " + folder + " (key " + digest + ": " + whose + ")");
    return true;
  };
  std::optional<FileLock> shared;
  if (!reuse(cache->previous, "the scene, its files and geometry unchanged") && !cache->shared.empty()) {
    shared = LockSharedRender(cache->shared, digest, [&](const std::string& holder) {
      Note(label + ": waiting for " + holder + ", which renders the same target scene");
    });
    reuse(SharedRenderFolder(cache->shared, digest), "the same scene, files and geometry as another job's");
  }
  if (!target->reused) {
    Note(label + ": rendering " + scene_file + ": " + why_not);
    Render(label, target);
  }
  KeepRender(target->light_field, *target->scene, digest, cache->next, reuse_from);
  if (shared && !target->reused) ShareRender(cache->next, cache->shared, digest);
}

}  // namespace
#endif

std::unique_ptr<Target> LoadOrRenderTarget(const SolveConfig& config, const std::string& label,
                                           const RenderCache* cache) {
#if LAYERLAB_WITH_EMBREE
  return LoadOrRenderTarget(config, label, cache, nullptr);
}

std::unique_ptr<Target> LoadOrRenderTarget(const SolveConfig& config, const std::string& label,
                                           const RenderCache* cache, std::unique_ptr<TargetScene> scene) {
#endif
  auto target = std::make_unique<Target>();
  if (!config.target.empty()) {
    target->source = config.target;
    Note(label + ": loading the light field " + config.target);
    if (config.target_moved_m != std::array<double, 3>{0, 0, 0})
      SayWarnings({"the light field " + config.target +
                   " is taken as it is, for an eye of a binocular pair with a display of its own: it must have been "
                   "rendered from that eye (a target scene is moved to it: docs/eye-pose.md)"});
    target->light_field = ReadLightField(config.target, {.load_depth = false});
    return target;
  }
  if (config.target_scene.empty())
    throw Error("no target: give \"solve\": {\"target\": LF_DIR} or {\"target_scene\": TARGET.json}");
  target->source = config.target_scene;
#if LAYERLAB_WITH_EMBREE
  target->scene = scene ? std::move(scene) : std::make_unique<TargetScene>(LoadTarget(config.target_scene));
  MoveTargetScene(target->scene.get(), config.target_moved_m);
  target->moved_m = config.target_moved_m;
  target->rendered = true;
  target->digest = TargetSceneDigest(*target->scene);
  ReadOrRender(config.target_scene, label, cache, target.get());
  target->tracer = std::make_unique<TargetTracer>(*target->scene);
  return target;
#else
  (void)cache;
  throw Error(config.target_scene +
              ": rendering a target scene needs Embree (this build has LAYERLAB_WITH_EMBREE=OFF); "
              "render it elsewhere with `layerlab render-target` and give the folder as \"target\"");
#endif
}

std::string DescribeTarget(const Target& target) {
  const LightFieldGeometry& g = target.light_field.geometry;
  std::string what = target.rendered ? "rendered from " + target.source + " (key " + target.digest +
                                           (target.reused ? ", the render of an earlier run reused" : "") + ")"
                                     : "light field " + target.source;
  return what + ": " + std::to_string(g.views_x) + " x " + std::to_string(g.views_y) + " views of " +
         std::to_string(g.cols) + " x " + std::to_string(g.rows) + " pixels";
}

LightFieldGeometry TargetGeometry(const SolveConfig& config) {
  if (!config.target.empty()) return ReadLightFieldGeometry(config.target);
  if (config.target_scene.empty())
    throw Error("no target: give \"solve\": {\"target\": LF_DIR} or {\"target_scene\": TARGET.json}");
  return LoadTarget(config.target_scene).geometry;
}

size_t RefuseSolveBeyondMemory(const DisplaySystem& system, const SolveConfig& config, int threads, size_t limit,
                               const std::string& limit_name) {
  return RefuseSolveBeyondMemory(system, TargetGeometry(config), config, threads, limit, limit_name);
}

size_t RefuseSolveBeyondMemory(const DisplaySystem& system, const LightFieldGeometry& geometry,
                               const SolveConfig& config, int threads, size_t limit, const std::string& limit_name) {
  // A rendered target keeps its depth map; one read from a folder is read without it (LoadOrRenderTarget).
  const bool rendered = config.target.empty();
  const MemoryEstimate need = EstimateSolveMemory(system, geometry, config.solver, config.options, config.sampling,
                                                  threads > 0 ? threads : omp_get_max_threads(), rendered);
  const bool machine = limit == 0;
  if (machine) limit = PhysicalMemory();
  if (limit > 0 && need.bytes > limit)
    throw Error("the solve needs about " + FormatBytes(double(need.bytes)) + " (" + need.breakdown + "), more than " +
                (machine ? "this machine's " + FormatBytes(double(limit)) + " of memory" : limit_name) +
                "; nothing was read or written");
  return need.bytes;
}

std::array<int, 2> WriteCenterView(const LightField& lf, const std::string& path) {
  const LightFieldGeometry& g = lf.geometry;
  const float* view = lf.view(g.view_index(g.views_y / 2, g.views_x / 2));
  const ShownPng png = WriteShownSrgbPng(path, g.cols, g.rows, std::vector<float>(view, view + g.pixels_per_view() * 3),
                                         kPreviewWidthPx);
  return {png.width, png.height};
}

}  // namespace layerlab
