// The flicker check of a time-multiplexed display (issue: "what a viewer
// perceives"). Over a frame of K subframes a region of the field shows the
// luminance L(t) its subframes' light gives, each subframe for 1 / (K f),
// relaxing between them as the panels respond (systems/lc_response.h). Its
// harmonics at n f (n = 1..K: the frame rate up to the panels' refresh rate),
//   c_n = sum_k sum_m (w_m / K) L_k(s_m) exp(-2 pi i n (k + s_m) / K)
// (the response's quadrature nodes s_m, w_m; L_k constant for instant
// panels), have modulation m_n = 2 |c_n| / c_0; the flicker is visible where
// m_n S(n f) > 1, S the eye's temporal contrast sensitivity for a disc of the
// region's area, mean luminance and eccentricity (eye/temporal_csf.h). The
// regions are squares of the visual field (2 deg by default: the fovea's
// scale), blocks of 4 x 4 of them, and the whole field (flicker over a
// larger area is visible at a lower modulation), over every ray of the
// light field (all pupil positions), gaze straight ahead. A display of one
// subframe is steady: no verdict.
#pragma once

#include <optional>

#include "layerlab/solvers/types.h"
#include "layerlab/systems/display_model.h"
#include "layerlab/systems/flicker_verdict.h"

namespace layerlab {

inline constexpr double kFlickerRegionDeg = 2;

// The verdict for patterns `t` on `model` (nullopt for one subframe); throws layerlab::Error for patterns
// that are not the display's layers.
std::optional<FlickerVerdict> CheckFlicker(const DisplayModel& model, const Patterns& t,
                                           double region_deg = kFlickerRegionDeg);
// The worst content a display can show, for `info`: a region (of region_deg, and the whole field) at the
// display's peak white in one subframe and dark in the others, on its fastest panel; nullopt for one subframe.
std::optional<FlickerVerdict> WorstCaseFlicker(const DisplaySystem& system, double region_deg = kFlickerRegionDeg);
// Sets report->flicker from the solve's patterns, when the solution is usable (a failure becomes a warning).
void AddFlickerCheck(const DisplayModel& model, const Patterns& t, SolverReport* report);

}  // namespace layerlab
