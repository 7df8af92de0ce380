// What every solver shares: the target made display-relative, the error of
// a set of patterns, and the initial guess.
#pragma once

#include <optional>
#include <string>

#include "framework/lightfield.h"
#include "solvers/solver.h"
#include "systems/display_model.h"

namespace layerlab {

// The most each channel can show: the sum of the branch weights.
std::array<float, 3> DisplayMaximum(const DisplayModel& model);

// Where values of `target` exceed the display's maximum: a copy with them
// clipped, or with the whole target scaled down by one factor, as `range`
// says; nothing (use `target` as it is) where none does. Records the count
// and factor in the report and warns when anything changed.
std::optional<LightField> PrepareTarget(const DisplayModel& model, const LightField& target, TargetRange range,
                                        SolverReport* report);

// Sum over rays and channels of (target - synthesized)^2, in double.
double Objective(const DisplayModel& model, const LightField& target, const Patterns& t);

// 10 log10(1 / MSE) with MSE = objective / samples; +inf for a perfect fit.
double PsnrDb(double objective, size_t samples);
// A PSNR for reports and tables: "31.42" with `decimals` digits, or "inf".
std::string FormatPsnr(double db, int decimals);

// Every pixel `initial_value`, or uniform in [0.25, 0.75] from `seed` when it is negative.
Patterns InitialPatterns(const DisplayModel& model, const SolverOptions& options);

// Throws layerlab::Error unless the display is bound to exactly the target's rays.
void RequireSameRays(const DisplayModel& model, const LightField& target);

}  // namespace layerlab
