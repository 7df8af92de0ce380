#include "layerlab/solvers/memory_estimate.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "layerlab/framework/error.h"
#include "layerlab/framework/heap_block.h"
#include "layerlab/framework/huge_page_allocator.h"
#include "layerlab/solvers/objective.h"
#include "layerlab/solvers/retinal_objective.h"
#include "layerlab/systems/lc_response.h"
#include "layerlab/systems/panel_diffraction.h"
#include "layerlab/systems/source_spread.h"

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

namespace {

// What the retinal objective adds (options.objective retinal, or the focal stack measured): what it keeps, and the
// larger of what it holds for a while in the set-up (while it is made; a measure: a synthesized light field and
// that synthesis's workspace) and in the iterations (the retinal pass's two light fields, joint pass and
// synthesis workspace; the measure of each iteration with the light-field objective).
struct RetinalParts {
  double kept = 0, setup = 0, steps = 0;
  std::string described;
};

RetinalParts RetinalPartsOf(const DisplayModel& model, const SolverOptions& options, int threads, double light_field) {
  RetinalParts r;
  const bool objective = options.objective == ObjectiveKind::kRetinal;
  if (!objective && !options.measure_focal_stack) return r;
  const RetinalObjectiveMemory m = RetinalObjectiveBytes(model, RetinalOptionsOf(options), threads);
  const double measure = light_field + double(SolveWorkspace::Layout(model, threads, kSynthesisPass).bytes());
  // The pass's light fields and joint pass, and the workspace of each synthesis it makes (no workspace given).
  const double pass = 2 * light_field + double(SolveWorkspace::Layout(model, threads, kJointPass).bytes()) +
                      double(SolveWorkspace::Layout(model, threads, kSynthesisPass).bytes());
  r.kept = double(m.kept());
  r.setup = std::max(double(m.construction), measure) + double(m.filter);
  r.steps = (objective ? pass : measure) + double(m.filter);
  r.described =
      " + the retinal objective " + FormatBytes(r.kept) + " (operator tables " + FormatBytes(double(m.tables)) +
      (m.pupils > 1 ? " of " + std::to_string(m.pupils) + " pupil positions" : std::string()) + ", images " +
      FormatBytes(double(m.images)) + " x " + std::to_string(m.pupils + 1) + ", apply buffer " +
      FormatBytes(double(m.apply_buffer)) + (m.pupils > 1 ? " x " + std::to_string(m.pupils) : std::string()) +
      (m.retina_workspace ? "; its target's images made in a workspace of " + FormatBytes(double(m.retina_workspace))
                          : std::string()) +
      "; in the set-up " + FormatBytes(r.setup) + ", in the iterations " + FormatBytes(r.steps) +
      (objective ? " with its pass" : "") + ")";
  return r;
}

// Making a branch's pair list behind real lenses (DisplayModel::pair_list)
// holds its set-up buffers beside what the solve has allocated by then; the
// lists themselves are resident once the workspace's layout has asked for them.
double PairListSetUpBytes(const DisplayModel& model, unsigned passes, int threads) {
  const bool pairs = (passes & kPairLatticePass) || ((passes & kPairLatticeIfOneBranch) && model.branch_count() == 1);
  double most = 0;
  for (size_t b = 0; pairs && b < model.branch_count(); ++b)
    if (model.pair_list(b)) {
      const std::vector<int>& layers = model.branch_layers(b);
      const int a = std::min(layers[0], layers[1]);
      most = std::max(most, double(MappedPairs::SetUpBytes(model.projection(a), threads)));
    }
  return most;
}

}  // namespace

MemoryEstimate EstimateSolveMemory(const DisplayModel& model, const std::string& solver, const SolverOptions& options,
                                   int threads, const LightField* target, bool rendered_target,
                                   const SolverRegistry& registry) {
  const SolverMemory& own = registry.get(solver).memory;
  threads = std::max(threads, 1);
  const LightFieldGeometry& g = model.geometry();
  const double light_field = double(LargeAllocationBytes(g.ray_count() * 3 * sizeof(float)));
  const bool depth_kept = target ? !target->depth.empty() : rendered_target;
  const double depth = depth_kept ? double(HeapBlockBytes(g.ray_count() * sizeof(float))) : 0;
  double layer_values = 0, patterns = 0;
  for (size_t k = 0; k < model.layer_count(); ++k) {
    const size_t values = model.projection(k).pixel_count() * 3;
    layer_values += double(values);
    patterns += double(HeapBlockBytes(values * sizeof(float)));
  }
  const double solver_fields = light_field * own.light_fields;
  // Each of the layer vectors is one huge-page block (quasi-newton's Vector).
  const double solver_layers =
      double(LargeAllocationBytes(static_cast<size_t>(layer_values * sizeof(double)))) * own.layer_doubles;
  // Where the panels' response matters the solve keeps the frame's light, one instant's light, the panels'
  // start values (double) and one instant's patterns: through it, in its pass (which runs through the joint
  // pass and synthesis, as it does through the panels' diffraction); without, for the shown PSNR at its end.
  const bool response = ResponseMatters(model.system());
  const bool plain =
      !(options.lc_response && response) && SeenKernels(model.system(), options.panel_diffraction).empty();
  // Through it, measuring the focal stack (the retinal objective's, or the light-field objective's measure)
  // reads the frame's light, made in two more.
  const bool measured = options.objective == ObjectiveKind::kRetinal || options.measure_focal_stack;
  const double response_bytes = response ? (options.lc_response && measured ? 4 : 2) * light_field + 3 * patterns : 0;
  const WorkspaceLayout layout =
      SolveWorkspace::Layout(model, threads, own.passes | (plain ? 0u : unsigned(kJointPass | kSynthesisPass)));
  const RetinalParts retinal = RetinalPartsOf(model, options, threads, light_field);
  const double pair_setup = PairListSetUpBytes(model, own.passes, threads);
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
  // The set-up (the solver's light fields, the retinal objective made) and the iterations (its layer vectors,
  // the retinal pass) in turn when the solver frees the one before the other; at once otherwise.
  const double solver_own = own.fields_then_layers
                                ? std::max(solver_fields + retinal.setup, solver_layers + retinal.steps)
                                : solver_fields + solver_layers + std::max(retinal.setup, retinal.steps);
  double counted = light_field + depth + solver_own + retinal.kept + patterns + response_bytes +
                   double(layout.bytes()) + pair_setup + program;
  if (e.clipped_copy_counted) counted += double(e.clipped_copy);
  e.counted = static_cast<size_t>(counted);
  e.margin = static_cast<size_t>(kMemoryMarginFraction * counted + kMemoryMarginBytes +
                                 (rendered_target ? kRenderMarginBytes : 0));
  // Rounded up to the last digit FormatBytes shows (0.1 MB below 1 GB, 0.01 GB from it: whole MB, whole 10 MB),
  // so that the figure the note and the refusal print is the bound itself.
  const double total = counted + double(e.margin), step = total >= 1e9 ? 1e7 : 1e6;
  e.bytes = static_cast<size_t>(std::ceil(total / step) * step);
  e.breakdown = "target " + FormatBytes(light_field);
  if (depth_kept) e.breakdown += " + its depth map " + FormatBytes(depth);
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
  if (response) e.breakdown += " + the LC response's light fields and start values " + FormatBytes(response_bytes);
  e.breakdown += retinal.described + " + patterns " + FormatBytes(patterns) + " + workspace " +
                 FormatBytes(double(layout.bytes())) + " (" + layout.Describe() + ")" +
                 (pair_setup > 0 ? " + making the pair lists " + FormatBytes(pair_setup) : "") + " + program " +
                 FormatBytes(program) + " + margin " + FormatBytes(double(e.margin));
  if (!target)
    e.breakdown += " (+ " + FormatBytes(light_field) + " for a clipped copy if the target exceeds the display's range)";
  return e;
}

MemoryEstimate EstimateSolveMemory(const DisplayModel& model, const std::string& solver, int threads,
                                   const LightField* target, const SolverRegistry& registry) {
  return EstimateSolveMemory(model, solver, registry.get(solver).defaults, threads, target, false, registry);
}

MemoryEstimate EstimateSolveMemory(const DisplaySystem& system, const LightFieldGeometry& g, const std::string& solver,
                                   const SolverOptions& options, Sampling sampling, int threads, bool rendered_target,
                                   const SolverRegistry& registry) {
  return EstimateSolveMemory(DisplayModel(system, g, sampling), solver, options, threads, nullptr, rendered_target,
                             registry);
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
