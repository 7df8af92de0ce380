// The forward model: the light field a display shows for a set of patterns,
// l~ = sum_b w_b prod_{k in b} P_k t_k (paper Eq. 3-5), view by view through
// the fast path where it applies (view_synthesizer.h). A public header: it
// names the workspace but does not pull the kernels in.
#pragma once

#include "layerlab/framework/lightfield.h"
#include "layerlab/systems/display_model.h"

namespace layerlab {

class SolveWorkspace;  // kernels/solve_workspace.h

// The display's light field of patterns `t`, with a workspace of its own: for
// a call outside a solve (retina, compare, the solution's light field).
LightField Synthesize(const DisplayModel& model, const Patterns& t);
// Into a light field of the model's geometry, reusing its memory; in
// `workspace` (with the synthesis pass) when given, else in one of its own.
void Synthesize(const DisplayModel& model, const Patterns& t, LightField* out, SolveWorkspace* workspace = nullptr);

}  // namespace layerlab
