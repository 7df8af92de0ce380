#include "layerlab/app/solver_flags.h"

#include "layerlab/framework/error.h"
#include "layerlab/framework/params.h"
#include "layerlab/solvers/solver_option_table.h"
#include "layerlab/systems/layer_sampler.h"

namespace layerlab::app {

void AddSolverFlags(CLI::App* cmd, SolverFlags& flags) {
  for (const SolverOptionEntry& e : SolverOptionTable()) {
    if (e.cli_flag.empty()) continue;
    if (e.kind != SolverOptionKind::kConfig) {
      AddOptionFlag(cmd, e, flags);
    } else if (e.key == "solver") {
      cmd->add_option(e.cli_flag, flags.solver,
                      e.cli_help + ": " + JoinWords(SolverRegistry::Builtins().names(), ", "));
    } else if (e.key == "sampling") {
      cmd->add_option(e.cli_flag, flags.sampling, e.cli_help);
    }  // --target, --target-scene: AddTargetOptions
  }
}

void ApplySolverFlags(const SolverFlags& flags, SolveConfig& config) {
  if (!flags.sampling.empty()) config.sampling = SamplingFromString(flags.sampling);
  ApplyOptionFlags(flags, SolverOptionTable(), config.options);
  // Checked here, before a target is read or rendered, with the field named by its flag.
  if (std::string why; !config.options.IsValid(&why)) throw Error(NameTheFlag(SolverOptionTable(), why, &flags));
}

}  // namespace layerlab::app
