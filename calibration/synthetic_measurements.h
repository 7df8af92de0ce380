// Synthetic measurements of a display whose true placement is known, for the
// tests and the example file. Markers are imaged through each layer's compiled
// ray transfer (the truth's: systems/compile.cpp composes it from the scene),
// by an explicit construction apart from marker_model.h's parameterization
// (the pixel counted from the other end on a flipped axis, the point placed
// by an Eigen rotation, the slope of the camera's ray solved from the
// transfer); noise is Gaussian from SplitMix64, the same numbers on every machine.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "layerlab/calibration/measurements.h"
#include "layerlab/systems/display_system.h"

namespace layerlab {

// Markers on a cols x rows grid over each panel's active region, inset by a
// fraction of it on every side; pixel centers.
struct MarkerGrid {
  int cols = 7, rows = 5;
  double inset = 0.1;
};

struct SyntheticCamera {
  std::optional<CameraIntrinsics> intrinsics;  // markers in camera pixels when set, as angles otherwise
  std::vector<std::array<double, 2>> positions_m = {{0.0, 0.0}};  // m, one capture each
  double pan_rad = 0, tilt_rad = 0, roll_rad = 0;                 // rad, as marker_model.h turns the camera
};

struct SyntheticNoise {
  double marker_sigma_rad = 0;  // rad per axis
  double outlier_fraction = 0;  // markers moved by outlier_size_rad, in a random direction
  double outlier_size_rad = 0;  // rad
  double luminance_sigma = 0;   // relative to the panel's maximum luminance
  uint64_t seed = 1;
};

// Panel pixel (col, row) of `layer` (full grid, the panel's own order, integers at pixel
// centers) as a point in its plane, m from the active region's center turned and offset as
// the panel is mounted, in eye-space order; PanelPixelAt is its inverse.
std::array<double, 2> PanelPoint(const VirtualLayer& layer, double col, double row);
std::array<double, 2> PanelPixelAt(const VirtualLayer& layer, const std::array<double, 2>& point);

// The panel point the ray from pupil point `position` (m) with tan-angle slope `slope`
// (x right, y up) meets, through the layer's compiled ray transfer; RaySlopeTo is its inverse.
std::array<double, 2> PanelPointOfRay(const VirtualLayer& layer, const std::array<double, 2>& position,
                                      const std::array<double, 2>& slope);
std::array<double, 2> RaySlopeTo(const VirtualLayer& layer, const std::array<double, 2>& point,
                                 const std::array<double, 2>& position);

// The visual angles (rad) at which `camera` sees panel pixel (col, row) of `layer`: behind real lenses by the
// exact trace (NaN where the lenses lose the rays to it), else by the ray transfer.
std::array<double, 2> ImagedMarker(const DisplaySystem& truth, const VirtualLayer& layer, double col, double row,
                                   const SyntheticCamera& camera, const std::array<double, 2>& position);

// One capture per camera position, every panel's grid in each.
std::vector<Capture> SyntheticCaptures(const DisplaySystem& truth, const MarkerGrid& grid,
                                       const SyntheticCamera& camera, const SyntheticNoise& noise);

// Luminance at 8-bit `codes` of L(x) = max (black + (1 - black) x^gamma), plus noise.
PanelLuminance SyntheticLuminance(const std::string& panel, const std::vector<int>& codes, double max_luminance,
                                  double black_level, double gamma, const SyntheticNoise& noise);

}  // namespace layerlab
