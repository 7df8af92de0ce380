// The exact gradient of an evaluation's light-field PSNR with respect to the
// design's variables, for a gradient-based local search (optimizer.local
// "slsqp"): one solve and one pass over the rays per evaluation, instead of
// two solves per variable for a difference.
//
// A solve's error at its solved patterns t*(x) is E(x) = min_t E(x, t). Where
// the solve has converged, the envelope theorem gives dE/dx = dE(x, t*)/dx at
// fixed patterns: the placement gradient (design/placement_gradient.h) of each
// layer's depth, centre and pitch, chained through how the compiled layers
// move with each variable. That last factor is the compile's (closed-form
// first-order optics) central difference at 1e-6 of the variable's range:
// its truncation error is O(1e-12) of the range against the solve's own
// convergence. PSNR = 10 log10(N / E), so dPSNR/dx = -10 / ln 10 (dE/dx) / E;
// several targets' PSNRs are averaged, and so are their gradients.
//
// Only what moves the layers is covered: a variable that changes anything
// else of the compiled display (a branch's weight, a layer's resolution, a
// real lens) is refused, naming it.
#pragma once

#include <vector>

#include "layerlab/design/design_evaluator.h"

namespace layerlab {

// What a design needs for the exact gradient: a single "psnr" objective, no
// constraint on a metric, bilinear sampling and a light-field solve without
// diffraction or the LC response. Returns "" when it is met, else why not.
std::string GradientProblem(const DesignSpec& spec);

// d(psnr)/dx of evaluation e (complete), in dB per the variables' units, from
// its jobs' scenes, targets and solved patterns. Throws layerlab::Error.
std::vector<double> PsnrGradient(const DesignSpec& spec, const DesignEvaluator& evaluator, const DesignEvaluation& e);

}  // namespace layerlab
