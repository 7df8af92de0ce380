// solve: the scene's "solve" section, the solver and its target; the command
// line overrides any of it. Paths are relative to the scene file's folder.
// A key of an option that the chosen solver does not read is refused.
//
// | key                   | type               | default                   | meaning                                  |
// |-----------------------|--------------------|---------------------------|------------------------------------------|
// | solver                | solver name        | the display's default     | multiplicative for one branch, additive-trust-region for one layer per branch, else hybrid |
// | target                | path               | none                      | a light-field folder (lightfield/1); not with target_scene |
// | target_scene          | path               | none                      | a target scene (layerlab-target/1) rendered with Embree |
// | iterations            | integer            | the solver's              | outer iterations                         |
// | sub_iterations        | integer            | the solver's              | hybrid and quasi-newton: updates of one multiplicative set before the next |
// | warm_start_iterations | integer            | the solver's              | quasi-newton: hybrid iterations before the quasi-Newton steps |
// | time_budget           | time               | 0 s (none)                | wall-clock budget                        |
// | tolerance             | fraction           | 0 (never)                 | stop when the objective changes by less than this, relative |
// | initial_value         | fraction           | the solver's              | initial transmittance; negative: random in [0.25, 0.75] |
// | seed                  | integer            | 1                         | for random initial patterns              |
// | threads               | integer            | 0 (every core; one per 16384 rays with the light-field objective) | worker threads (report.json `threads`: how many the solve ran on) |
// | sampling              | nearest, bilinear  | nearest                   | how the light field samples the layers   |
// | target_range          | clip, scale        | clip                      | target values beyond what the display shows: clipped, or the target scaled |
// | objective             | lightfield, retinal | lightfield               | what is minimized: the light-field error, or the retinal error over the eye's accommodation_range in 0.2 D steps (quasi-newton, joint; docs/retinal-objective.md) |
// | contrast_sensitivity  | boolean            | false                     | the retinal objective's residuals weighted by the eye's contrast sensitivity (Mannos and Sakrison 1974, 1 up to its 7.9 cpd peak) |
// | retinal_target        | lightfield, traced | lightfield                | the retinal objective's target images (and the focal-stack PSNR's): natural viewing of the target light field, or traced from target_scene ray by ray (needs a target scene; seconds per state) |
#include "solvers/solve_config.h"

#include <algorithm>
#include <filesystem>

#include "framework/params.h"

namespace layerlab {

std::string ResolveAgainstScene(const Scene& scene, const std::string& path) {
  std::filesystem::path p = path;
  if (p.is_absolute()) return p.string();
  return (std::filesystem::path(scene.file).parent_path() / p).lexically_normal().string();
}

std::string DefaultSolverFor(const DisplaySystem& system) { return SolverRegistry::Builtins().DefaultFor(system); }

std::string ObjectiveRefusal(const std::string& solver, ObjectiveKind objective, const SolverRegistry& registry) {
  if (objective == ObjectiveKind::kLightField || registry.get(solver).retinal_objective) return "";
  std::vector<std::string> able;
  for (const std::string& name : registry.names())
    if (registry.get(name).retinal_objective) able.push_back(name);
  return "the solver \"" + solver + "\" minimizes the light-field objective only; the retinal objective needs " +
         JoinWords(able, " or ");
}

SolveConfig ReadSolveConfig(const Scene& scene, const DisplaySystem& system, const SolverRegistry& registry) {
  SolveConfig config;
  config.solver = registry.DefaultFor(system);
  if (!scene.document.contains("solve")) {
    config.options = registry.get(config.solver).defaults;
    return config;
  }
  Params p(scene.document["solve"], {scene.file, "/solve"});
  config.solver = p.string("solver", config.solver);
  const SolverType* type = registry.find(config.solver);
  if (!type) {
    try {
      registry.get(config.solver);
    } catch (const Error& e) {
      p.fail("solver", e.message());
    }
  }
  // A key that sets an option of other solvers only is an error, not ignored.
  for (const std::string& name : registry.names())
    for (const SolverOptionKey& key : registry.get(name).options)
      if (p.has(key.key) && !type->Reads(key.key)) {
        std::vector<std::string> readers;
        for (const std::string& reader : registry.names())
          if (registry.get(reader).Reads(key.key)) readers.push_back(reader);
        p.fail(key.key, "the solver \"" + config.solver + "\" does not read it (" + JoinWords(readers, ", ") + " do)");
      }
  SolverOptions& o = config.options;
  o = type->defaults;
  if (p.has("target") && p.has("target_scene"))
    p.fail("target_scene",
           "give \"target\" (a light-field folder) or \"target_scene\" (a target scene to render), not both");
  if (p.has("target")) config.target = ResolveAgainstScene(scene, p.string("target"));
  if (p.has("target_scene")) config.target_scene = ResolveAgainstScene(scene, p.string("target_scene"));
  o.iterations = static_cast<int>(p.integer("iterations", 1, 1000000, o.iterations));
  o.sub_iterations = static_cast<int>(p.integer("sub_iterations", 1, 1000, o.sub_iterations));
  o.warm_start_iterations = static_cast<int>(p.integer("warm_start_iterations", 0, 1000000, o.warm_start_iterations));
  o.time_budget = p.quantity("time_budget", Dimension::kTime, o.time_budget);
  p.require_range("time_budget", o.time_budget, 0, 1e7, false, false);
  o.tolerance = p.quantity("tolerance", Dimension::kFraction, o.tolerance);
  p.require_range("tolerance", o.tolerance, 0, 1, false, true);
  o.initial_value = p.quantity("initial_value", Dimension::kFraction, o.initial_value);
  p.require_range("initial_value", o.initial_value, -1, 1, false, false);
  o.seed = static_cast<uint64_t>(p.integer("seed", 0, INT64_MAX, static_cast<int64_t>(o.seed)));
  o.threads = static_cast<int>(p.integer("threads", 0, 1024, o.threads));
  config.sampling =
      p.choice("sampling", {"nearest", "bilinear"}, "nearest") == "nearest" ? Sampling::kNearest : Sampling::kBilinear;
  o.target_range =
      p.choice("target_range", {"clip", "scale"}, "clip") == "clip" ? TargetRange::kClip : TargetRange::kScale;
  o.objective = p.choice("objective", {"lightfield", "retinal"}, "lightfield") == "retinal"
                    ? ObjectiveKind::kRetinal
                    : ObjectiveKind::kLightField;
  if (const std::string why = ObjectiveRefusal(config.solver, o.objective, registry); !why.empty())
    p.fail("objective", why);
  o.retinal.target = p.choice("retinal_target", {"lightfield", "traced"}, "lightfield") == "traced"
                         ? RetinalTarget::kTraced
                         : RetinalTarget::kLightField;
  if (o.retinal.target == RetinalTarget::kTraced && p.has("target"))
    p.fail("retinal_target",
           "\"traced\" traces the target scene, and \"target\" is a light-field folder; give "
           "\"target_scene\"");
  o.retinal.contrast_sensitivity = p.boolean("contrast_sensitivity", false);
  p.check_all_read();
  return config;
}

}  // namespace layerlab
