// solve: the scene's "solve" section, the solver and its target; the command
// line overrides any of it. Paths are relative to the scene file's folder.
// A key of an option that the chosen solver does not read is refused.
//
// Its keys, their ranges and defaults are the option table's
// (solvers/solver_option_table.h, docs/scene-reference.md).
#include "layerlab/solvers/solve_config.h"

#include <algorithm>
#include <filesystem>

#include "layerlab/framework/option_reader.h"
#include "layerlab/framework/params.h"
#include "layerlab/solvers/solver_option_table.h"

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

std::array<double, 3> TargetSceneMove(const EyeModel& eye) {
  return eye.binocular ? PairFrameInDisplayFrame(*eye.binocular) : std::array<double, 3>{0, 0, 0};
}

SolveConfig ReadSolveConfig(const Scene& scene, const DisplaySystem& system, const SolverRegistry& registry) {
  SolveConfig config;
  config.solver = registry.DefaultFor(system);
  config.target_moved_m = TargetSceneMove(system.eye);
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
  for (const SolverOptionEntry& e : SolverOptionTable())
    if (e.in_scene) ReadOptionEntry(p, e, &o);
  const SolverOptionEntry& sampling = *FindSolverOption("sampling");
  config.sampling = p.choice("sampling", sampling.choices, sampling.default_text) == "nearest" ? Sampling::kNearest
                                                                                               : Sampling::kBilinear;
  if (const std::string why = ObjectiveRefusal(config.solver, o.objective, registry); !why.empty())
    p.fail("objective", why);
  if (o.retinal.target == RetinalTarget::kTraced && p.has("target"))
    p.fail("retinal_target",
           "\"traced\" traces the target scene, and \"target\" is a light-field folder; give "
           "\"target_scene\"");
  p.check_all_read();
  return config;
}

}  // namespace layerlab
