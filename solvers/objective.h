// What every solver shares: the target made display-relative, the error of
// a set of patterns, and the initial guess.
#pragma once

#include <optional>
#include <string>

#include "layerlab/framework/lightfield.h"
#include "layerlab/kernels/solve_workspace.h"
#include "layerlab/metrics/psnr.h"
#include "layerlab/solvers/solver.h"
#include "layerlab/systems/display_model.h"

namespace layerlab {

// The most each channel can show: the sum of the branch weights.
std::array<float, 3> DisplayMaximum(const DisplayModel& model);

// Where values of `target` exceed the display's maximum: a copy with them
// clipped, or with the whole target scaled down by one factor, as `range`
// says; nothing (use `target` as it is) where none does. Records the count
// and factor in the report and warns when anything changed.
std::optional<LightField> PrepareTarget(const DisplayModel& model, const LightField& target, TargetRange range,
                                        SolverReport* report);

// "Far below": the shipped displays end at 27.9 to 35.7 dB on the dice
// (docs/performance.md, docs/time-multiplexing.md); a solve that ends more
// than 10 dB under the lowest of them, under kFarBelowPsnrDb, is far below
// what a display reaches.
inline constexpr double kFarBelowPsnrDb = 18.0;
// A share of target values above the display's maximum, or a branch giving
// less than this fraction of the brightest branch's luminance, is named as a cause.
inline constexpr double kOutOfRangeCause = 0.01, kDimBranchCause = 0.5;
// A fixed backlight pattern lit on less than this share of its plane (pinlights) is named as a cause: most rays
// then meet none of its light.
inline constexpr double kDarkEmissionCause = 0.25;

// The warning for a usable solve that ended under kFarBelowPsnrDb, with its
// causes when they are found (the out-of-range target share, unequal branch
// brightness, a backlight dark on most of its plane); nothing for a solve at or above it.
std::optional<std::string> FarBelowWarning(const DisplayModel& model, const SolverReport& report);

// Sum over rays and channels of (target - synthesized)^2, in double: in the
// solve's workspace (sized with kSynthesisPass), or without one in a
// workspace of its own (for a call outside a solve: tests, compare).
double Objective(const DisplayModel& model, const LightField& target, const Patterns& t, SolveWorkspace* workspace);
double Objective(const DisplayModel& model, const LightField& target, const Patterns& t);

// A PSNR for reports and tables: "31.42" with `decimals` digits, or "inf".
std::string FormatPsnr(double db, int decimals);

// Every pixel `initial_value`, or uniform in [0.25, 0.75] from `seed` when it is negative; a layer with a
// fixed pattern (PanelSpec::fixed_pattern) shows it, an LED layer holds values only at its sites.
Patterns InitialPatterns(const DisplayModel& model, const SolverOptions& options);

// Writes each fixed layer's pattern into `t` and sets each LED layer's pixels between its sites to 0
// (systems/source_spread.h): a warm start's patterns may hold others.
void HoldLayerConstraints(const DisplayModel& model, Patterns* t);
// Whether layer k shows a fixed pattern: the solvers leave it as it is.
inline bool IsFixedLayer(const DisplayModel& model, size_t k) {
  return model.system().layers[k].panel.fixed_pattern != nullptr;
}
// Whether layer k is fixed or solved only in part (an LED array's sites): the solvers that move every pixel of
// every layer (SolverType::fixed_layers false) refuse it.
bool IsConstrainedLayer(const DisplayModel& model, size_t k);

// Throws layerlab::Error unless the display is bound to exactly the target's rays.
void RequireSameRays(const DisplayModel& model, const LightField& target);

}  // namespace layerlab
