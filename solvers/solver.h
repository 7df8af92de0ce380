// Solvers factorize a target light field into layer patterns for a display:
//   argmin_t || l - sum_b w_b prod_{k in b} P_k t_k ||^2,  0 <= t <= 1   (paper Eq. 6)
// Options in, a report out (in the manner of ceres::Solver): a plain options
// struct with IsValid(), and a report that starts as "not run", holds the
// termination reason, a trace row per iteration (error against wall time),
// BriefReport(), FullReport() and IsSolutionUsable(). Solve() does not throw
// for bad options or a failed run: the report says what happened.
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "layerlab/framework/lightfield.h"
#include "layerlab/solvers/types.h"
#include "layerlab/systems/display_model.h"

namespace layerlab {

class Solver {
 public:
  virtual ~Solver() = default;
  // `patterns` holds one pattern per layer; it is initialised by the solver.
  virtual SolverReport Solve(const DisplayModel& model, const LightField& target, const SolverOptions& options,
                             Patterns* patterns) const = 0;
};

// A "solve" key of a scene file that sets a SolverOptions field
// (solvers/solve_config.cpp reads them all).
struct SolverOptionKey {
  std::string key;      // the JSON key, also the field's name
  std::string meaning;  // one line, for listings
};
// The keys every solver reads (the solve loop's: iterations, time_budget, ...).
const std::vector<SolverOptionKey>& CommonSolverOptionKeys();
// sub_iterations: the hybrid's, read also by quasi-newton's warm start.
SolverOptionKey SubIterationsKey();

// Everything the rest of the program knows about a solver: adding one is its
// file and a line in builtin_solvers.def (or SolverRegistry::add at run time).
struct SolverType {
  SolverType() = default;
  SolverType(std::string name_, std::string summary_, std::function<std::unique_ptr<Solver>()> make_,
             SolverOptions defaults_ = {})
      : name(std::move(name_)), summary(std::move(summary_)), make(std::move(make_)), defaults(std::move(defaults_)) {}

  std::string name;
  std::string summary;
  std::function<std::unique_ptr<Solver>()> make;
  SolverOptions defaults;  // what this solver runs with unless told otherwise
  // Why it cannot factorize `system`, worded to follow the solver's name
  // ("needs a display of one branch; ..."), or "" when it can. Empty: every display.
  std::function<std::string(const DisplaySystem&)> unsuitable;
  // Among the solvers that suit a display, the one of highest rank is its
  // default (the most specific fit); 0: never chosen by default.
  int default_rank = 0;
  SolverMemory memory;
  // It minimizes the retinal objective when SolverOptions::objective asks (else only the light-field one).
  bool retinal_objective = false;
  // It solves through the panels' diffraction when SolverOptions::panel_diffraction asks (else it refuses a
  // display whose panels diffract).
  bool panel_diffraction = false;
  // It leaves a layer with a fixed pattern (PanelSpec::fixed_pattern: a printed mask) as it is (else it refuses
  // a display that has one).
  bool fixed_layers = false;
  // It solves through the panels' LC response when SolverOptions::lc_response asks (else it refuses a display
  // whose panels respond in finite time across subframes).
  bool lc_response = false;
  // The keys it reads beyond CommonSolverOptionKeys().
  std::vector<SolverOptionKey> options;

  std::string Unsuitable(const DisplaySystem& system) const { return unsuitable ? unsuitable(system) : ""; }
  bool Reads(const std::string& key) const;  // a common key or one of `options`
};

class SolverRegistry {
 public:
  void add(SolverType type);  // fails if the name is taken
  const SolverType* find(const std::string& name) const;
  std::vector<std::string> names() const;
  // Throws layerlab::Error listing the known names for an unknown one.
  const SolverType& get(const std::string& name) const;
  std::unique_ptr<Solver> create(const std::string& name) const { return get(name).make(); }
  // The suitable solver of highest default_rank; throws layerlab::Error when none suits.
  std::string DefaultFor(const DisplaySystem& system) const;

  static const SolverRegistry& Builtins();
  static SolverRegistry WithBuiltins();  // a copy to add to

 private:
  std::map<std::string, SolverType> types_;
};

// Why the named solver cannot factorize `system`, or "" when it can; throws
// layerlab::Error for an unknown name.
std::string UnsuitableSolver(const std::string& solver, const DisplaySystem& system,
                             const SolverRegistry& registry = SolverRegistry::Builtins());

}  // namespace layerlab
