// The data flow of layerlab, phase by phase, each with the file that holds it
// (in the manner of Mitsuba's parser.h). Including this header gives the
// library's core; the optional phases (target rendering with Embree,
// calibration with Ceres) are named where they enter and included on their own.
//
//  1. Scene JSON -> elements          systems/scene.h       LoadScene / ParseScene
//     Each element object is built by its type (elements/registry.h,
//     builtin_elements.def: one file and one line per element type); the
//     scene keeps the whole document for the later phases ("solve", "run").
//
//  2. Elements -> compiled system     systems/compile.h     Compile
//     The optical path is walked from the eye: virtual layers in eye space,
//     grouped into branches that add, each a product of its layers
//     (systems/display_system.h, paper Fig. 1 right). Nothing downstream sees
//     the elements again.
//     (Calibration refits a compiled system to measurements:
//     calibration/calibration.h Calibrate, with Ceres.)
//
//  3. Target                          framework/lightfield_io.h   ReadLightField
//     A light field on the eyebox (docs/lightfield-format.md), or a target
//     scene rendered to one (targets/target_renderer.h RenderTarget, with Embree).
//
//  4. Light-field operators           systems/display_model.h     DisplayModel
//     The system bound to the target's rays: one projection P_k per layer
//     (systems/projection.h, sampling in systems/layer_sampler.h) and the
//     branch weights, l~ = sum_b w_b prod_k P_k t_k (paper Eq. 3-5).
//     The fast path over the rays     kernels/synthesis.h         Synthesize
//     reads the model and nothing above it (kernels/): the one-tap views
//     and their row kernels, the pixel-pair lattice, the multiplicative
//     update's and the joint pass's sums, and the passes' working memory,
//     one per solve, per thread and shared (kernels/solve_workspace.h).
//     The eye's physiology (eye/) and what it sees (retina/retina.h) sit
//     on top of the model and the kernels.
//
//  5. Solver                          solvers/solve_config.h      ReadSolveConfig
//     The "solve" section picks a solver of the registry (solvers/solver.h,
//     builtin_solvers.def: one file and one line per solver; each states the
//     displays it suits, its memory and its keys) and its options; the
//     memory a solve needs is checked first (solvers/memory_estimate.h,
//     from the workspace's layout). Solve() runs the shared loop
//     (solvers/solve_loop.h: target prepared, workspace made, trace, stop)
//     and returns a report; the objective: solvers/objective.h.
//
//  6. Outputs                         solvers/solution_writer.h   WriteSolution
//     Patterns, panel-ready images, report and trace, each file switched into
//     place whole (framework/atomic_file.h).
//
//  7. Analysis                        analysis/
//     What the eye sees over accommodation (analysis/retina_sweep.h over
//     retina/retina.h), contrast against frequency (analysis/contrast.h),
//     several displays and solvers on one target (analysis/compare.h), the
//     "run" section and its report (analysis/run_config.h,
//     analysis/html_report.h). The command line (app/) calls these phases.
#pragma once

#include "layerlab/analysis/compare.h"
#include "layerlab/analysis/retina_sweep.h"
#include "layerlab/analysis/run_config.h"
#include "layerlab/elements/registry.h"
#include "layerlab/framework/lightfield_io.h"
#include "layerlab/kernels/synthesis.h"
#include "layerlab/solvers/memory_estimate.h"
#include "layerlab/solvers/solution_writer.h"
#include "layerlab/solvers/solve_config.h"
#include "layerlab/solvers/solver.h"
#include "layerlab/systems/compile.h"
#include "layerlab/systems/display_model.h"
#include "layerlab/systems/scene.h"
