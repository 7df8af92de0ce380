#include <algorithm>

#include "layerlab/framework/error.h"
#include "layerlab/framework/params.h"
#include "layerlab/solvers/solver.h"

namespace layerlab {

#define LAYERLAB_SOLVER(Name, file) SolverType Name##SolverType();
#include "layerlab/solvers/builtin_solvers.def"
#undef LAYERLAB_SOLVER

bool SolverType::Reads(const std::string& key) const {
  auto named = [&](const SolverOptionKey& o) { return o.key == key; };
  const std::vector<SolverOptionKey>& common = CommonSolverOptionKeys();
  return std::any_of(common.begin(), common.end(), named) || std::any_of(options.begin(), options.end(), named);
}

void SolverRegistry::add(SolverType type) {
  std::string name = type.name;
  if (!type.make) throw Error("solver \"" + name + "\" has no factory");
  if (!types_.emplace(name, std::move(type)).second) throw Error("solver \"" + name + "\" is registered twice");
}

const SolverType* SolverRegistry::find(const std::string& name) const {
  auto it = types_.find(name);
  return it == types_.end() ? nullptr : &it->second;
}

std::vector<std::string> SolverRegistry::names() const {
  std::vector<std::string> out;
  for (const auto& [name, type] : types_) out.push_back(name);
  return out;
}

const SolverType& SolverRegistry::get(const std::string& name) const {
  if (const SolverType* type = find(name)) return *type;
  std::string msg = "unknown solver \"" + name + "\"";
  if (auto near = ClosestWord(name, names())) msg += "; did you mean \"" + *near + "\"?";
  throw Error(msg + " Known solvers: " + JoinWords(names(), ", "));
}

std::string SolverRegistry::DefaultFor(const DisplaySystem& system) const {
  const SolverType* best = nullptr;
  for (const auto& [name, type] : types_)
    if (type.default_rank > 0 && (!best || type.default_rank > best->default_rank) && type.Unsuitable(system).empty())
      best = &type;
  if (!best) throw Error("no registered solver is a default for this display (" + JoinWords(names(), ", ") + ")");
  return best->name;
}

std::string UnsuitableSolver(const std::string& solver, const DisplaySystem& system, const SolverRegistry& registry) {
  return registry.get(solver).Unsuitable(system);
}

SolverRegistry SolverRegistry::WithBuiltins() {
  SolverRegistry r;
#define LAYERLAB_SOLVER(Name, file) r.add(Name##SolverType());
#include "layerlab/solvers/builtin_solvers.def"
#undef LAYERLAB_SOLVER
  return r;
}

const SolverRegistry& SolverRegistry::Builtins() {
  static const SolverRegistry registry = WithBuiltins();
  return registry;
}

}  // namespace layerlab
