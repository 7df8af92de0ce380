// layerlab: the command-line front end. Every failure is one message on
// stderr, location first, and a non-zero exit.
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <optional>

#include <CLI/CLI.hpp>

#include "layerlab/app/command_help.h"
#include "layerlab/app/command_line.h"
#include "layerlab/app/commands.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/interrupt.h"
#include "layerlab/framework/progress.h"
#include "layerlab/framework/version.h"
#include "layerlab/kernels/row_kernels.h"

int main(int argc, char** argv) {
  layerlab::app::SetCommandLine(argc, argv);
  CLI::App app{"layerlab: model, factorize and analyse layered light-field near-eye displays"};
  app.require_subcommand(1);
  app.set_version_flag("--version", layerlab::VersionLine(), "Print the version (and the git commit) and exit");
  layerlab::app::AddInfoCommand(app);
  layerlab::app::AddRunCommand(app);
  layerlab::app::AddSweepCommand(app);
  layerlab::app::AddSolveCommand(app);
  layerlab::app::AddContrastCommand(app);
  layerlab::app::AddRetinaCommand(app);
  layerlab::app::AddEyeboxCommand(app);
  layerlab::app::AddCompareCommand(app);
  layerlab::app::AddToleranceCommand(app);
  layerlab::app::AddPsfCommand(app);
#if LAYERLAB_WITH_CERES
  layerlab::app::AddFitCommand(app);
  layerlab::app::AddCalibrationPatternsCommand(app);
  layerlab::app::AddPhotographCommand(app);
  layerlab::app::AddDetectCommand(app);
  layerlab::app::AddCameraPatternsCommand(app);
  layerlab::app::AddCameraIntrinsicsCommand(app);
#endif
#if LAYERLAB_WITH_EMBREE
  layerlab::app::AddRenderTargetCommand(app);
#endif
  // How much every command says on stderr: one pair of flags, read here for all of them.
  // Set as the flag is read, before the command's callback runs.
  for (CLI::App* cmd : app.get_subcommands({})) {
    CLI::Option* q = cmd->add_flag_function(
        "--quiet,-q", [](std::int64_t) { layerlab::SetVerbosity(layerlab::Verbosity::kQuiet); },
        "No progress or notes on stderr (errors and warnings remain)");
    cmd->add_flag_function(
           "--verbose,-v", [](std::int64_t) { layerlab::SetVerbosity(layerlab::Verbosity::kVerbose); },
           "Every step on stderr: each iteration of each run, one line each")
        ->excludes(q);
  }
  // `layerlab help [COMMAND]`, and a first word that is no command named as such with the closest one.
  if (std::optional<int> code = layerlab::app::HelpOrUnknownCommand(app, argc, argv)) return *code;
  // Past a file-size limit, write() should fail with EFBIG (and the atomic
  // writers clean up) instead of the process dying half-way.
  std::signal(SIGXFSZ, SIG_IGN);
  try {
    layerlab::ActiveRowKernels();  // a bad LAYERLAB_ROW_KERNELS is an error here, not inside a parallel loop
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const layerlab::InterruptedError& e) {
    std::fprintf(stderr, "layerlab: %s\n", e.what());
    return 130;
  } catch (const layerlab::Error& e) {
    std::fprintf(stderr, "layerlab: error: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "layerlab: internal error: %s\n", e.what());
    return 3;
  }
  return 0;
}
