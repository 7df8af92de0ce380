// solve: the scene's "solve" section, the solver and its target; the command
// line overrides any of it. Paths are relative to the scene file's folder.
// A key of an option that the chosen solver does not read is refused.
//
// Its keys, their ranges and defaults are the option table's
// (solvers/solver_option_table.h, docs/scene-reference.md).
#include "layerlab/solvers/solve_config.h"

#include <algorithm>
#include <filesystem>

#include "layerlab/framework/params.h"
#include "layerlab/solvers/solver_option_table.h"

namespace layerlab {

namespace {

// One option of the section, into its SolverOptions field (the section's own keys, kConfig, are read by hand).
void ReadOption(Params& p, const SolverOptionEntry& e, SolverOptions* o) {
  switch (e.kind) {
    case SolverOptionKind::kInteger:
      o->*e.integer = static_cast<int>(
          p.integer(e.key, static_cast<int64_t>(e.range.min), static_cast<int64_t>(e.range.max), o->*e.integer));
      break;
    case SolverOptionKind::kSeed:
      if (p.has(e.key)) {
        const nlohmann::json& v = p.raw(e.key);
        if (!v.is_number_unsigned()) p.fail(e.key, "must be an integer in [0, 2^64 - 1], got " + v.dump());
        o->*e.seed = v.get<uint64_t>();
      }
      break;
    case SolverOptionKind::kReal:
      o->*e.real = p.quantity(e.key, e.dimension, o->*e.real);
      p.require_range(e.key, o->*e.real, e.range.min, e.range.max, e.range.min_open, e.range.max_open);
      break;
    case SolverOptionKind::kChoice:
      e.set(*o, e.ChoiceIndex(p.choice(e.key, e.choices, e.choices[e.get(*o)])));
      break;
    case SolverOptionKind::kBoolean:
      e.set(*o, p.boolean(e.key, e.get(*o) != 0));
      break;
    case SolverOptionKind::kConfig:
      break;
  }
}

}  // namespace

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
  for (const SolverOptionEntry& e : SolverOptionTable())
    if (e.in_scene) ReadOption(p, e, &o);
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
