// What a solve will hold at its peak, estimated before anything of
// light-field size is allocated, so that a run that cannot fit is refused
// up front with the estimate instead of failing (or swapping) half-way.
#pragma once

#include <cstddef>
#include <string>

#include "layerlab/framework/lightfield.h"
#include "layerlab/solvers/solver.h"
#include "layerlab/systems/display_system.h"

namespace layerlab {

// What the estimate adds for what it cannot count from an allocation's size,
// measured against the peak (VmHWM) of `solve` and of the test's child
// processes (tests/solve_memory_test.cpp, tests/cli/solve_memory_examples.sh;
// docs/performance.md, memory): the library code and the thread pools that
// reading, writing and reporting bring in after the estimate (3.4-4.0 MB
// measured), the allocator's slack (freed blocks glibc keeps, per-thread
// arenas: the fraction); and for a target rendered in the process, Embree's
// scene and build blocks and TBB's workers (2.4 MB more measured).
inline constexpr double kMemoryMarginFraction = 0.01;
inline constexpr double kMemoryMarginBytes = 5e6;
inline constexpr double kRenderMarginBytes = 3e6;

struct MemoryEstimate {
  // counted + margin, rounded up to what FormatBytes shows (a whole MB; 10 MB from 1 GB on): an upper bound of
  // the solve's peak.
  size_t bytes = 0;
  size_t counted = 0;  // the parts below, each from its allocation's size
  // kMemoryMarginFraction of `counted` + kMemoryMarginBytes (+ kRenderMarginBytes for a rendered target)
  size_t margin = 0;
  // A copy of the target with the values the display cannot show clipped or
  // scaled (SolveLoop makes it only then). Counted in `bytes` when the
  // target is known to need it; stated apart (and not counted) when the
  // target was not read yet.
  size_t clipped_copy = 0;
  bool clipped_copy_counted = false;
  size_t workspace = 0;  // SolveWorkspace::Layout's bytes
  size_t program = 0;    // what the process held when estimated
  // "target 162.2 MB + the solver's light fields 162.2 MB x 1 + patterns 3.8 MB + workspace 38.9 MB (per thread
  // ...) + program 14.2 MB (+ 162.2 MB for a clipped copy if the target exceeds the display's range)"
  std::string breakdown;
};

// What a solve of `solver` with `options` holds at its peak: the target as
// read, the solver's own light fields and layer vectors (SolverType::memory),
// the patterns, the solve's workspace as SolveWorkspace::Layout lays it out
// for the solver's passes and `threads` (the very sizes SolveLoop
// allocates), the retinal objective's tables, images and passes when
// options.objective is retinal or the focal stack is measured
// (RetinalObjectiveBytes), and the program (what this process holds now,
// VmRSS: call it before the target is read), plus the margin above. With
// `target` the clipped copy is counted when a pass over the target's values
// finds one above the display's maximum. Not counted: a traced retinal
// target's scene (held by whoever renders it).
// `rendered_target`: the target is rendered in this process, and keeps its
// depth map, one float per ray (a target read from a folder is read without
// it); with `target` its depth map is counted when it has one.
MemoryEstimate EstimateSolveMemory(const DisplayModel& model, const std::string& solver, const SolverOptions& options,
                                   int threads, const LightField* target = nullptr, bool rendered_target = false,
                                   const SolverRegistry& registry = SolverRegistry::Builtins());
// The same with the solver's default options.
MemoryEstimate EstimateSolveMemory(const DisplayModel& model, const std::string& solver, int threads,
                                   const LightField* target = nullptr,
                                   const SolverRegistry& registry = SolverRegistry::Builtins());
// The same from the display and the target's geometry alone (the target not read yet).
MemoryEstimate EstimateSolveMemory(const DisplaySystem& system, const LightFieldGeometry& geometry,
                                   const std::string& solver, const SolverOptions& options, Sampling sampling,
                                   int threads, bool rendered_target,
                                   const SolverRegistry& registry = SolverRegistry::Builtins());
MemoryEstimate EstimateSolveMemory(const DisplaySystem& system, const LightFieldGeometry& geometry,
                                   const std::string& solver, int threads,
                                   const SolverRegistry& registry = SolverRegistry::Builtins());

// What this process holds now (VmRSS of /proc/self/status), or 0 when unknown.
size_t ResidentBytes();

// "512 MB", "2 GB", "1.5 GiB", or a bare number of bytes; throws layerlab::Error naming `option`.
size_t ParseByteSize(const std::string& text, const std::string& option);
std::string FormatBytes(double bytes);  // "162.2 MB"

// The machine's physical memory, or 0 when unknown.
size_t PhysicalMemory();

}  // namespace layerlab
