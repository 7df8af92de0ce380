// Everything a solve leaves on disk, each file written atomically:
//   patterns/<layer>.exr     the optimizer's patterns (linear transmittance,
//                            panel pixel order: mirrored where the layer is)
//   panels/<panel>.png       panel-ready 8-bit images: gamma- and
//                            black-level-encoded for the panel, placed at the
//                            active region of the panel's full pixel grid
//   trace.csv                iteration, seconds, objective, psnr_db (and focal_stack_psnr_db with the retinal objective)
//   report.txt, report.json  the solver's report
//   lightfield/              the synthesized light field (on request)
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "layerlab/solvers/solver.h"
#include "layerlab/systems/display_model.h"

namespace layerlab {

struct PanelEncoding {
  std::vector<uint8_t> pixels;   // [row][col][rgb] over the whole panel
  size_t below_black_level = 0;  // values the panel cannot make as dark as asked
  int cols = 0, rows = 0;        // the whole panel's pixels
  int active_cols = 0, active_rows = 0, active_left = 0, active_top = 0;  // the pixels the pattern drives
};

// Encodes a layer's pattern for its panel: code = 255 ((t - b) / (1 - b))^(1/gamma). An LED array
// (systems/source_spread.h) is driven one value per LED: its panel is its LEDs' grid, not its fine one.
PanelEncoding EncodeForPanel(const VirtualLayer& layer, const LayerPattern& pattern);

// A layer's pattern in the eye's orientation (x right, y up as the eye sees the layer): the panel's pixel
// order with the layer's mirror reversals undone (systems/display_system.h, flip_x and flip_y); [row][col][rgb].
std::vector<float> AsTheEyeSeesIt(const VirtualLayer& layer, const LayerPattern& pattern);

nlohmann::json ReportToJson(const SolverReport& report);
// report.json without its trace: what `solve --json` and `run --json` print.
nlohmann::json ReportSummaryJson(const SolverReport& report);
std::string TraceCsv(const SolverReport& report);

// A pattern is transmittance: every value finite and in [0, 1]. Throws
// Error("<what>: pixel (row 2, col 3) channel G is NaN; ...") for the first
// that is not. ReadPatterns holds each file to it, the Python module each array.
void CheckTransmittance(const LayerPattern& pattern, const std::string& what);

// Loads patterns written by WriteSolution back (for retinal images and
// analysis), each checked with CheckTransmittance.
Patterns ReadPatterns(const DisplayModel& model, const std::string& folder);

struct SolutionFiles {
  bool write_lightfield = false;
};
// Returns the files written, relative to `folder`.
std::vector<std::string> WriteSolution(const DisplayModel& model, const Patterns& t, const SolverReport& report,
                                       const std::string& folder, const SolutionFiles& what = {});

}  // namespace layerlab
