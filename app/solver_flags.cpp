#include "layerlab/app/solver_flags.h"

#include "layerlab/app/number_list.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/params.h"
#include "layerlab/solvers/solver_option_table.h"
#include "layerlab/systems/layer_sampler.h"

namespace layerlab::app {

void AddSolverFlags(CLI::App* cmd, SolverFlags& flags) {
  for (const SolverOptionEntry& e : SolverOptionTable()) {
    if (e.cli_flag.empty()) continue;
    switch (e.kind) {
      case SolverOptionKind::kConfig:
        if (e.key == "solver")
          cmd->add_option(e.cli_flag, flags.solver,
                          e.cli_help + ": " + JoinWords(SolverRegistry::Builtins().names(), ", "));
        else if (e.key == "sampling")
          cmd->add_option(e.cli_flag, flags.sampling, e.cli_help);
        break;  // --target, --target-scene: AddTargetOptions
      case SolverOptionKind::kInteger:
        cmd->add_option(e.cli_flag, flags.integers[e.key], e.cli_help);
        break;
      case SolverOptionKind::kReal:
        if (e.dimension == Dimension::kTime)
          cmd->add_option(e.cli_flag, flags.texts[e.key], e.cli_help);
        else
          cmd->add_option(e.cli_flag, flags.reals[e.key], e.cli_help);
        break;
      case SolverOptionKind::kChoice:
        cmd->add_option(e.cli_flag, flags.texts[e.key], e.cli_help);
        break;
      case SolverOptionKind::kBoolean:
        cmd->add_flag(e.cli_flag, flags.switches[e.key], e.cli_help);
        break;
      case SolverOptionKind::kSeed:
        throw Error("solver option " + e.key + ": no command-line flag of this kind");
    }
  }
}

void ApplySolverFlags(const SolverFlags& flags, SolveConfig& config) {
  SolverOptions& o = config.options;
  if (!flags.sampling.empty()) config.sampling = SamplingFromString(flags.sampling);
  for (const SolverOptionEntry& e : SolverOptionTable()) {
    if (e.cli_flag.empty()) continue;
    switch (e.kind) {
      case SolverOptionKind::kInteger:
        if (const std::optional<int>& v = flags.integers.at(e.key)) o.*e.integer = *v;
        break;
      case SolverOptionKind::kReal:
        if (e.dimension == Dimension::kTime) {
          const std::string& text = flags.texts.at(e.key);
          if (!text.empty()) o.*e.real = ParseOptionValue(text, e.cli_flag, kSeconds);
        } else if (const std::optional<double>& v = flags.reals.at(e.key)) {
          o.*e.real = *v;
        }
        break;
      case SolverOptionKind::kChoice:
        if (const std::string& text = flags.texts.at(e.key); !text.empty()) {
          const int index = e.ChoiceIndex(text);
          if (index < 0) throw Error(e.cli_flag + ": \"" + text + "\" is not one of " + e.ChoiceList());
          e.set(o, index);
        }
        break;
      case SolverOptionKind::kBoolean:
        if (flags.switches.at(e.key)) e.set(o, 1);
        break;
      case SolverOptionKind::kSeed:
      case SolverOptionKind::kConfig:
        break;
    }
  }
}

}  // namespace layerlab::app
