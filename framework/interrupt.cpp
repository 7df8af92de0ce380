#include "layerlab/framework/interrupt.h"

#include <csignal>

namespace layerlab {
namespace {

volatile std::sig_atomic_t interrupted = 0;

extern "C" void OnInterrupt(int) {
  interrupted = 1;
  std::signal(SIGINT, SIG_DFL);  // a second Ctrl-C ends the process
}

}  // namespace

void InstallInterruptHandler() {
  interrupted = 0;
  std::signal(SIGINT, OnInterrupt);
}

bool Interrupted() { return interrupted != 0; }

}  // namespace layerlab
