// What a solve will hold at its peak, estimated before anything of
// light-field size is allocated, so that a run that cannot fit is refused
// up front with the estimate instead of failing (or swapping) half-way.
#pragma once

#include <cstddef>
#include <string>

#include "framework/lightfield.h"
#include "solvers/solver.h"
#include "systems/display_system.h"

namespace layerlab {

struct MemoryEstimate {
  size_t bytes = 0;
  std::string breakdown;  // "target 162.2 MB x 3 (...) + layers ... + program 64 MB"
};

// The common part plus what the solver's type states (SolverType::memory).
MemoryEstimate EstimateSolveMemory(const DisplaySystem& system, const LightFieldGeometry& geometry,
                                   const std::string& solver, int threads,
                                   const SolverRegistry& registry = SolverRegistry::Builtins());

// "512 MB", "2 GB", "1.5 GiB", or a bare number of bytes; throws layerlab::Error naming `option`.
size_t ParseByteSize(const std::string& text, const std::string& option);
std::string FormatBytes(double bytes);  // "162.2 MB"

// The machine's physical memory, or 0 when unknown.
size_t PhysicalMemory();

}  // namespace layerlab
