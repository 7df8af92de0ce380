// From photographs to measurements (OpenCV; built with LAYERLAB_WITH_OPENCV):
// the chessboard corners of each capture found to sub-pixel accuracy
// (cv::findChessboardCorners, cv::cornerSubPix), matched to their panel
// pixels, and each luminance step read as the mean linear value over the
// middle of the panel's image divided by the exposure; the result is the
// "layerlab-measurements/1" that `layerlab fit` reads (docs/calibration.md).
//
// A photograph that fails is reported by name with the reason (overexposed,
// pattern not found with what the image shows instead, too few features,
// another plan's board, a mirrored or turned board) and the rest go on.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "layerlab/calibration/capture_plan.h"
#include "layerlab/calibration/measurements.h"
#include "layerlab/calibration/photo_files.h"
#include "layerlab/systems/display_system.h"

namespace layerlab {

// A photograph as linear light, fraction of full scale, [row][col].
struct Photo {
  int width = 0, height = 0;
  std::vector<float> pixels;
};

// Reads a linear EXR (channel Y, else G) or an 8- or 16-bit PNG (gray, or the
// mean of RGB), by the file's own signature whatever its extension, applying
// the plan's response ("linear" or "gamma G"). Throws layerlab::Error naming
// the file.
Photo ReadPhoto(const std::string& path, const std::string& response);

struct PhotoCheck {
  double overexposed_fraction = 0.005;  // more pixels than this at full scale: overexposed
};

struct FoundCorners {
  std::vector<std::array<double, 2>> panel_pixels;   // (col, row)
  std::vector<std::array<double, 2>> camera_pixels;  // (u, v)
};

// The chessboard's inner corners in `photo`, ordered to match the camera
// pixels `predicted` for the board's corners (row-major from its top left)
// best; the reason when they are not found.
struct CornerSearch {
  std::optional<FoundCorners> corners;
  std::string reason;
};
CornerSearch FindChessboardCorners(const Photo& photo, const Chessboard& board,
                                   const std::vector<std::array<double, 2>>& predicted, const PhotoCheck& check = {});

// A printed chessboard of squares_x x squares_y squares anywhere in `photo`,
// with no prediction of where (camera intrinsics, camera_calibration.h): its
// inner corners to sub-pixel accuracy, row by row as OpenCV orders them (from
// either end: the grid of corners reads the same turned by 180 degrees, which
// only changes the pose it is fitted with); or, when it is not found, the
// reason: overexposed, another board (its square counts), too noisy, out of
// focus, or no board in view.
struct BoardCorners {
  std::vector<std::array<double, 2>> camera_pixels;  // (u, v); empty when not found
  std::string reason;
};
BoardCorners FindPrintedChessboard(const Photo& photo, int squares_x, int squares_y, const PhotoCheck& check = {});

// Why a photograph cannot be used as it is, or empty.
std::string OverexposureReason(const Photo& photo, const PhotoCheck& check);

struct PhotoFailure {
  std::string photo, reason;
};

struct Detection {
  Measurements measurements;
  std::vector<PhotoFailure> failures;
  // Said once: photographs read from another file or format than the plan names (notes), boards whose
  // orientation their colours cannot show (warnings).
  std::vector<std::string> notes, warnings;
  size_t corners = 0, luminance_steps = 0;
};

// Every capture of `plan` in `folder`, matched through `designed` (the scene
// as designed: its optics predict where each corner appears, which orders the
// board). `camera`: the intrinsics; the plan's when empty (one is needed).
// `format`: which file each photograph is read from (photo_files.h). Each
// photograph of a panel repeated at one camera position is kept, as one more
// capture at that position.
Detection DetectCaptures(const std::string& folder, const CapturePlan& plan, const DisplaySystem& designed,
                         const std::optional<CameraIntrinsics>& camera, const PhotoCheck& check = {},
                         PhotoFormat format = PhotoFormat::kAuto);

}  // namespace layerlab
