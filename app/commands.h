// The layerlab subcommands; each Add*Command registers its options and a
// callback on the top-level CLI11 app.
#pragma once

#include <CLI/CLI.hpp>

namespace layerlab::app {

void AddInfoCommand(CLI::App& app);
void AddSolveCommand(CLI::App& app);
void AddContrastCommand(CLI::App& app);
void AddCompareCommand(CLI::App& app);  // compare SCENES... --target LF_DIR --out DIR
void AddRetinaCommand(CLI::App& app);   // retina SCENE.json --patterns DIR --out DIR
void AddEyeboxCommand(CLI::App& app);   // eyebox SCENE.json --patterns DIR --target-scene T.json --out DIR
void AddRunCommand(CLI::App& app);      // run SCENE.json --out DIR: the main job and its report
void AddSweepCommand(CLI::App& app);    // sweep SWEEP.json --out DIR: a grid of jobs, one table
// optimize DESIGN.json --out DIR: the display's design optimized by NLopt, each evaluation a run
void AddOptimizeCommand(CLI::App& app);
// tolerance SCENE.json --out DIR: Monte Carlo over assembly tolerances
void AddToleranceCommand(CLI::App& app);
void AddPsfCommand(CLI::App& app);  // psf SCENE.json --out DIR: the eye's PSF and OTF by its pupil function
#if LAYERLAB_WITH_CERES
void AddFitCommand(CLI::App& app);                  // fit SCENE.json MEASUREMENTS.json --out CALIBRATED.json
void AddCalibrationPatternsCommand(CLI::App& app);  // calibration-patterns SCENE.json --out DIR
void AddPhotographCommand(CLI::App& app);           // photograph CAPTURES_DIR --scene BUILT.json --out DIR
void AddDetectCommand(CLI::App& app);  // detect CAPTURES_DIR --scene SCENE.json --out MEASUREMENTS.json (OpenCV)
void AddCameraPatternsCommand(CLI::App& app);    // camera-patterns --out DIR: a chessboard to print, the photos to take
void AddCameraIntrinsicsCommand(CLI::App& app);  // camera-intrinsics DIR --out CAMERA.json (OpenCV)
#endif
#if LAYERLAB_WITH_EMBREE
void AddRenderTargetCommand(CLI::App& app);  // render-target TARGET.json --out DIR
#endif

}  // namespace layerlab::app
