// What to photograph to estimate the measuring camera's intrinsics
// ("layerlab-camera-captures/1", docs/calibration.md step 1): a flat printed
// chessboard of known square size, seen at several poses, each photograph
// named with the tilt and the place in the frame it should have. Tilts of 20
// to 40 degrees about both axes are what determine the focal length (a board
// seen face-on gives only focal length over distance); boards near the frame's
// corners are what determine the distortion.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace layerlab {

inline constexpr const char* kCameraCapturesFormat = "layerlab-camera-captures/1";
// The plan's file in its folder; the photographs lie beside it.
inline constexpr const char* kCameraCapturesFile = "camera_captures.json";

// The printed board: squares_x x squares_y squares of square_m each, its top-left square dark, one square of
// white margin around it; printed from `image`, pixels_per_square image pixels to a square.
struct PrintedChessboard {
  int squares_x = 10, squares_y = 7;
  double square_m = 0.02;
  std::string image = "chessboard.png";
  int pixels_per_square = 100;

  int corners_x() const { return squares_x - 1; }
  int corners_y() const { return squares_y - 1; }
  int image_width() const { return (squares_x + 2) * pixels_per_square; }
  int image_height() const { return (squares_y + 2) * pixels_per_square; }
};

struct PlannedBoardPhoto {
  std::string photo;  // file name, relative to the plan's folder
  // The board's tilt: about the frame's horizontal axis (positive: its top edge away from the camera) and
  // about the vertical axis (positive: its right edge away), rad.
  std::array<double, 2> tilt_rad = {0, 0};
  std::array<double, 2> center_in_frame = {0.5, 0.5};  // the board's center, fractions of width and height
  double width_in_frame = 0.6;                         // the board's squares, fraction of the frame's width
  std::string advice;                                  // the same in words
};

struct CameraCapturePlan {
  std::string description;
  // How a photograph's pixel values relate to linear light: "linear", or "gamma G" (value^G).
  std::string response = "linear";
  PrintedChessboard board;
  std::vector<PlannedBoardPhoto> photos;
};

struct CameraPlanOptions {
  int squares_x = 10, squares_y = 7;
  double square_m = 0.02;
  int poses = 12;  // 3 to 100
  std::string photo_extension = "png";
};

// Throws layerlab::Error naming the option when one is out of range.
CameraCapturePlan PlanCameraCaptures(const CameraPlanOptions& options);

// The board to print, 8-bit gray, [row][col], image_width() x image_height().
std::vector<uint8_t> PrintedChessboardImage(const PrintedChessboard& board);

nlohmann::ordered_json CameraCapturePlanToJson(const CameraCapturePlan& plan);
// Strict (framework/params.h): unknown keys refused, errors with the file and pointer.
CameraCapturePlan ParseCameraCapturePlan(const nlohmann::json& document, const std::string& file);
CameraCapturePlan ReadCameraCapturePlanFile(const std::string& path);

}  // namespace layerlab
