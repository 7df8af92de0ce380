// What to photograph to calibrate a built display ("layerlab-captures/1",
// docs/calibration.md): per panel a chessboard in its active region seen from
// each camera position, and a luminance ramp (one uniform level per
// photograph) seen from the first; every capture names the image each panel
// shows, the camera position and the exposure, and the photograph's file.
//
// While one panel is measured the panels its light passes through show white
// (transparent) and the panels of the other branches show black, so that no
// other light adds to what is measured.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "layerlab/calibration/camera_model.h"
#include "layerlab/systems/display_system.h"

namespace layerlab {

inline constexpr const char* kCapturesFormat = "layerlab-captures/1";

// The largest photograph, in pixels, that `detect` decodes and `photograph`
// renders (a 64 Mpixel float image is 256 MB; EXR's own limit is the same).
inline constexpr size_t kMaxPhotoPixels = size_t{64} << 20;

// A chessboard of squares_x x squares_y squares, each square_pixels wide, its
// top-left square (dark) at panel pixel (left, top) of the full grid.
struct Chessboard {
  std::string panel;
  int squares_x = 10, squares_y = 6;
  int square_pixels = 0;
  int64_t left = 0, top = 0;

  int corners_x() const { return squares_x - 1; }
  int corners_y() const { return squares_y - 1; }
  // Inner corner (a, b), a across and b down from the top left, in panel
  // pixels (col, row; integers at pixel centers, so a corner is at a half).
  std::array<double, 2> corner(int a, int b) const;
  // Whether panel pixel (col, row) lies in a dark square.
  bool dark(int64_t col, int64_t row) const;
};

enum class CaptureKind { kChessboard, kLuminance };

struct PlannedCapture {
  std::string photo;  // file name of the photograph, relative to the captures folder
  CaptureKind kind = CaptureKind::kChessboard;
  std::string panel;  // the panel measured
  int level = 255;    // kLuminance: the 8-bit level it shows everywhere in its active region
  std::array<double, 2> camera_position = {0, 0};  // m, in the eye's pupil plane, x right, y up
  double exposure = 1;                             // relative to the plan's base exposure
  // Panel name -> the pattern file it shows (relative to the captures folder).
  std::vector<std::pair<std::string, std::string>> show;
};

struct CapturePlan {
  std::string description;
  std::vector<Chessboard> chessboards;  // one per panel
  std::vector<PlannedCapture> captures;
  // The camera's intrinsics when known from elsewhere; detect estimates them otherwise.
  std::optional<CameraIntrinsics> camera;
  // How a photograph's pixel values relate to linear light: "linear", or "gamma G" (value^G).
  std::string response = "linear";

  const Chessboard* chessboard(const std::string& panel) const;
};

// Why a chessboard of squares_x x squares_y squares cannot be used, or empty:
// OpenCV's corner finder needs at least 3 x 3 inner corners (4 x 4 squares),
// and a board of as many corners across as down can be found turned by 90
// degrees, which the ordering by the prediction does not undo.
std::string ChessboardSquaresProblem(int64_t squares_x, int64_t squares_y);

// The exponent G of a response "linear" (1) or "gamma G" (finite, > 0, nothing after it); nullopt for anything else.
std::optional<double> ResponseExponent(const std::string& response);

struct PlanOptions {
  int squares_x = 10, squares_y = 6;  // per chessboard; one square of white margin is kept around it
  std::vector<std::array<double, 2>> positions = {{0, 0}, {2e-3, 0}, {0, 2e-3}};  // m
  std::vector<int> levels;                                                        // 8-bit; empty: 0, 16, ..., 240, 255
  std::string photo_extension = "exr";
};

// Throws layerlab::Error when a panel's active region cannot hold the board
// with squares of at least 4 pixels, or the display is time-multiplexed.
CapturePlan PlanCaptures(const DisplaySystem& system, const PlanOptions& options);

// The image panel `panel` shows for pattern file `name` ("<panel>_chessboard.png",
// "<panel>_level_<NNN>.png", "<panel>_white.png", "<panel>_black.png"): 8-bit
// gray, [row][col], the panel's full grid; outside the active region black.
std::vector<uint8_t> PatternImage(const DisplaySystem& system, const CapturePlan& plan, const std::string& panel,
                                  const std::string& name);
// Every pattern file the plan shows, each once, as (panel, name).
std::vector<std::pair<std::string, std::string>> PatternFiles(const CapturePlan& plan);
inline constexpr const char* kPatternFolder = "patterns";

nlohmann::ordered_json CapturePlanToJson(const CapturePlan& plan);
// Strict (framework/params.h): unknown keys refused, errors with the file and pointer.
CapturePlan ParseCapturePlan(const nlohmann::json& document, const std::string& file);
CapturePlan ReadCapturePlanFile(const std::string& path);

}  // namespace layerlab
