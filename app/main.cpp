// layerlab: the command-line front end. Every failure is one message on
// stderr, location first, and a non-zero exit.
#include <csignal>
#include <cstdio>
#include <exception>

#include <CLI/CLI.hpp>

#include "app/commands.h"
#include "framework/error.h"
#include "framework/interrupt.h"
#include "systems/row_kernels.h"

int main(int argc, char** argv) {
  CLI::App app{"layerlab: model, factorize and analyse layered light-field near-eye displays"};
  app.require_subcommand(1);
  layerlab::app::AddInfoCommand(app);
  layerlab::app::AddRunCommand(app);
  layerlab::app::AddSolveCommand(app);
  layerlab::app::AddContrastCommand(app);
  layerlab::app::AddRetinaCommand(app);
  layerlab::app::AddCompareCommand(app);
#if LAYERLAB_WITH_CERES
  layerlab::app::AddFitCommand(app);
#endif
#if LAYERLAB_WITH_EMBREE
  layerlab::app::AddRenderTargetCommand(app);
#endif
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
