#include "framework/error.h"
#include "framework/params.h"
#include "solvers/solver.h"

namespace layerlab {

#define LAYERLAB_SOLVER(Name) SolverType Name##SolverType();
#include "solvers/builtin_solvers.def"
#undef LAYERLAB_SOLVER

void SolverRegistry::add(SolverType type) {
  std::string name = type.name;
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

std::unique_ptr<Solver> SolverRegistry::create(const std::string& name) const {
  if (const SolverType* type = find(name)) return type->make();
  std::string msg = "unknown solver \"" + name + "\"";
  if (auto near = ClosestWord(name, names())) msg += "; did you mean \"" + *near + "\"?";
  throw Error(msg + " Known solvers: " + JoinWords(names(), ", "));
}

const SolverRegistry& SolverRegistry::Builtins() {
  static const SolverRegistry registry = [] {
    SolverRegistry r;
#define LAYERLAB_SOLVER(Name) r.add(Name##SolverType());
#include "solvers/builtin_solvers.def"
#undef LAYERLAB_SOLVER
    return r;
  }();
  return registry;
}

}  // namespace layerlab
