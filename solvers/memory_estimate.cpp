#include "solvers/memory_estimate.h"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "framework/error.h"

namespace layerlab {

std::string FormatBytes(double bytes) {
  char text[32];
  if (bytes >= 1e9)
    std::snprintf(text, sizeof text, "%.2f GB", bytes / 1e9);
  else
    std::snprintf(text, sizeof text, "%.1f MB", bytes / 1e6);
  return text;
}

MemoryEstimate EstimateSolveMemory(const DisplaySystem& system, const LightFieldGeometry& g, const std::string& solver,
                                   int threads, const SolverRegistry& registry) {
  const SolverMemory& own = registry.get(solver).memory;
  threads = std::max(threads, 1);
  const double light_field = double(g.ray_count()) * 3 * sizeof(float);
  // The target as read and, if values exceed the display, its clipped or
  // scaled copy, then the solver's own light fields.
  const int copies = 2 + own.light_fields;
  double layer_pixels = 0;
  for (const VirtualLayer& layer : system.layers) layer_pixels += double(layer.cols) * layer.rows * 3;
  // Patterns (float), merged sums (2 double), per-thread sums (2 float), kept ratios (double), the solver's own.
  double layers = layer_pixels * (4 + 16 + 8.0 * threads + 8);
  if (own.layer_doubles > 0) layers += layer_pixels * 8 * own.layer_doubles;
  const double views = double(g.pixels_per_view()) * 3 * sizeof(float) * 4 * threads;  // per-thread view buffers
  const double program = 64e6;  // code, libraries, the thread pool
  MemoryEstimate e;
  e.bytes = static_cast<size_t>(copies * light_field + layers + views + program);
  e.breakdown = "target " + FormatBytes(light_field) + " x " + std::to_string(copies) + " + layers " +
                FormatBytes(layers) + " + view buffers " + FormatBytes(views) + " + program " + FormatBytes(program);
  return e;
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
