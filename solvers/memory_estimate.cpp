#include "solvers/memory_estimate.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "framework/error.h"
#include "framework/huge_page_allocator.h"
#include "solvers/objective.h"

namespace layerlab {

std::string FormatBytes(double bytes) {
  char text[32];
  if (bytes >= 1e9)
    std::snprintf(text, sizeof text, "%.2f GB", bytes / 1e9);
  else
    std::snprintf(text, sizeof text, "%.1f MB", bytes / 1e6);
  return text;
}

size_t ResidentBytes() {
  std::FILE* status = std::fopen("/proc/self/status", "r");
  if (!status) return 0;
  char line[256];
  size_t kb = 0;
  while (std::fgets(line, sizeof line, status))
    if (std::sscanf(line, "VmRSS: %zu kB", &kb) == 1) break;
  std::fclose(status);
  return kb * 1024;
}

MemoryEstimate EstimateSolveMemory(const DisplayModel& model, const std::string& solver, int threads,
                                   const LightField* target, const SolverRegistry& registry) {
  const SolverMemory& own = registry.get(solver).memory;
  threads = std::max(threads, 1);
  const LightFieldGeometry& g = model.geometry();
  const double light_field = double(g.ray_count()) * 3 * sizeof(float);
  double layer_values = 0;
  for (size_t k = 0; k < model.layer_count(); ++k) layer_values += double(model.projection(k).pixel_count()) * 3;
  const double patterns = layer_values * sizeof(float);
  const double solver_fields = light_field * own.light_fields;
  // Each of the layer vectors is one huge-page block (quasi-newton's Vector).
  const double solver_layers =
      double(LargeAllocationBytes(static_cast<size_t>(layer_values * sizeof(double)))) * own.layer_doubles;
  const WorkspaceLayout layout = SolveWorkspace::Layout(model, threads, own.passes);
  // Code, libraries and what the process holds before the solve; 64 MB where it cannot be read.
  const size_t resident = ResidentBytes();
  const double program = resident ? double(resident) : 64e6;

  MemoryEstimate e;
  e.workspace = layout.bytes();
  e.program = static_cast<size_t>(program);
  e.clipped_copy = static_cast<size_t>(light_field);
  if (target) {
    const std::array<float, 3> max = DisplayMaximum(model);
    for (size_t k = 0; k < target->rgb.size() && !e.clipped_copy_counted; ++k)
      e.clipped_copy_counted = target->rgb[k] > max[k % 3];
  }
  const double solver_own =
      own.fields_then_layers ? std::max(solver_fields, solver_layers) : solver_fields + solver_layers;
  double total = light_field + solver_own + patterns + double(layout.bytes()) + program;
  if (e.clipped_copy_counted) total += double(e.clipped_copy);
  e.bytes = static_cast<size_t>(total);
  e.breakdown = "target " + FormatBytes(light_field);
  if (e.clipped_copy_counted) e.breakdown += " + its clipped copy " + FormatBytes(light_field);
  const std::string fields =
      "the solver's light fields " + FormatBytes(light_field) + " x " + std::to_string(own.light_fields);
  const std::string layers = "the solver's layer vectors " + FormatBytes(solver_layers);
  if (own.fields_then_layers && own.light_fields > 0 && own.layer_doubles > 0)
    e.breakdown += " + the larger of " + fields + " and " + layers + " (held in turn)";
  else {
    if (own.light_fields > 0) e.breakdown += " + " + fields;
    if (own.layer_doubles > 0) e.breakdown += " + " + layers;
  }
  e.breakdown += " + patterns " + FormatBytes(patterns) + " + workspace " + FormatBytes(double(layout.bytes())) + " (" +
                 layout.Describe() + ") + program " + FormatBytes(program);
  if (!target)
    e.breakdown += " (+ " + FormatBytes(light_field) + " for a clipped copy if the target exceeds the display's range)";
  return e;
}

MemoryEstimate EstimateSolveMemory(const DisplaySystem& system, const LightFieldGeometry& g, const std::string& solver,
                                   int threads, const SolverRegistry& registry) {
  return EstimateSolveMemory(DisplayModel(system, g), solver, threads, nullptr, registry);
}

size_t ParseByteSize(const std::string& text, const std::string& option) {
  size_t used = 0;
  double value = 0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  std::string unit = text.substr(used);
  while (!unit.empty() && unit.front() == ' ') unit.erase(0, 1);
  double scale = 0;
  if (unit.empty() || unit == "B")
    scale = 1;
  else if (unit == "kB" || unit == "KB")
    scale = 1e3;
  else if (unit == "MB")
    scale = 1e6;
  else if (unit == "GB")
    scale = 1e9;
  else if (unit == "KiB")
    scale = 1024.0;
  else if (unit == "MiB")
    scale = 1024.0 * 1024;
  else if (unit == "GiB")
    scale = 1024.0 * 1024 * 1024;
  if (used == 0 || scale == 0 || !std::isfinite(value) || !(value > 0) || value * scale > 1e15)
    throw Error(option + ": \"" + text + "\" is not a memory size (give e.g. 512 MB, 2 GB or 1.5 GiB)");
  return static_cast<size_t>(value * scale);
}

size_t PhysicalMemory() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
  return pages > 0 && page > 0 ? static_cast<size_t>(pages) * static_cast<size_t>(page) : 0;
}

}  // namespace layerlab
