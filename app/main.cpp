// layerlab: the command-line front end. Every failure is one message on
// stderr, location first, and an exit status that says which kind
// (app/exit_status.h, docs/cli.md).
#include <csignal>
#include <cstdio>
#include <exception>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "layerlab/app/command_help.h"
#include "layerlab/app/command_line.h"
#include "layerlab/app/command_result.h"
#include "layerlab/app/commands.h"
#include "layerlab/app/exit_status.h"
#include "layerlab/app/global_flags.h"
#include "layerlab/app/renamed_options.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/interrupt.h"
#include "layerlab/framework/version.h"
#include "layerlab/kernels/row_kernels.h"

namespace {

using namespace layerlab::app;

void AddCommands(CLI::App& app) {
  AddInfoCommand(app);
  AddRunCommand(app);
  AddSweepCommand(app);
  AddOptimizeCommand(app);
  AddSolveCommand(app);
  AddContrastCommand(app);
  AddRetinaCommand(app);
  AddEyeboxCommand(app);
  AddCompareCommand(app);
  AddToleranceCommand(app);
  AddPsfCommand(app);
#if LAYERLAB_WITH_CERES
  AddFitCommand(app);
  AddCalibrationPatternsCommand(app);
  AddPhotographCommand(app);
  AddDetectCommand(app);
  AddCameraPatternsCommand(app);
  AddCameraIntrinsicsCommand(app);
#endif
#if LAYERLAB_WITH_EMBREE
  AddRenderTargetCommand(app);
#endif
  AddHelpCommand(app);
  AddGlobalFlags(app);
  AddRenamedOptions(app);
}

// The subcommand the command line named, "" when none was reached.
std::string Named(CLI::App& app) {
  const std::vector<CLI::App*> parsed = app.get_subcommands();
  return parsed.empty() ? "" : parsed.back()->get_name();
}

// The error on stderr (and with --json on stdout) and its status.
int Fail(const std::string& command, const std::string& kind, const std::string& message, int status) {
  std::fprintf(stderr, "layerlab: %s%s\n", kind.c_str(), message.c_str());
  PrintFailure(command, message, status, JsonRequested());
  return status;
}

int Run(CLI::App& app, int argc, char** argv) {
  try {
    layerlab::ActiveRowKernels();  // a bad LAYERLAB_ROW_KERNELS is an error here, not inside a parallel loop
    app.parse(argc, argv);
  } catch (const CLI::RuntimeError& e) {  // a command's own status (sweep: a job failed), already explained
    PrintFailure(Named(app), e.what(), e.get_exit_code(), JsonRequested());
    return e.get_exit_code();
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) return app.exit(e);  // --help, --version
    const std::string command = Named(app);
    // A value CLI11 could not read or its check refused is a refused input, as any value layerlab refuses;
    // the rest (an unknown option, a missing argument) is the command line itself.
    const bool value = dynamic_cast<const CLI::ValidationError*>(&e) || dynamic_cast<const CLI::ConversionError*>(&e);
    return Fail(command, "error: ",
                (command.empty() ? "" : command + ": ") + e.what() + " (layerlab help" +
                    (command.empty() ? "" : " " + command) + ")",
                value ? kExitRefused : kExitUsage);
  } catch (const UsageError& e) {
    return Fail(Named(app), "error: ", e.what(), kExitUsage);
  } catch (const layerlab::InterruptedError& e) {
    return Fail(Named(app), "", e.what(), kExitInterrupted);
  } catch (const layerlab::Error& e) {
    return Fail(Named(app), "error: ", e.what(), kExitRefused);
  } catch (const std::exception& e) {
    return Fail(Named(app), "internal error: ", e.what(), kExitInternal);
  }
  return kExitDone;
}

}  // namespace

int main(int argc, char** argv) {
  SetCommandLine(argc, argv);
  CLI::App app{"layerlab: model, factorize and analyse layered light-field near-eye displays", "layerlab"};
  app.require_subcommand(1);
  app.set_version_flag("--version", layerlab::VersionLine(), "Print the version (and the git commit) and exit");
  AddCommands(app);
  if (std::optional<int> status = RefuseUnknownCommand(app, argc, argv)) return *status;
  // Past a file-size limit, write() should fail with EFBIG (and the atomic
  // writers clean up) instead of the process dying half-way.
  std::signal(SIGXFSZ, SIG_IGN);
  return Run(app, argc, argv);
}
