// The measuring camera's intrinsics from photographs of a printed chessboard
// (`layerlab camera-intrinsics`, docs/calibration.md step 1; OpenCV): the
// board's corners found in each photograph of a camera capture plan
// (photo_detection.h: FindPrintedChessboard), then cv::calibrateCamera with
// the model of camera_model.h (fx, fy, cx, cy, k1, k2; OpenCV's tangential
// terms p1, p2 and k3 held at 0, which makes its distortion camera_model.h's),
// and the standard deviation of each intrinsic from the estimate's covariance
// scaled by the residual variance over the residuals' degrees of freedom.
//
// A photograph that cannot be used is named with the reason and the rest go
// on. The estimate is refused, with the reason, when fewer than 3 photographs
// show the board, or when the poses leave the focal length undetermined (a
// board seen face-on in every photograph gives only focal length over
// distance): its standard deviation above kMaxFocalLengthRelativeStd of it.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "layerlab/calibration/camera_capture_plan.h"
#include "layerlab/calibration/camera_model.h"
#include "layerlab/calibration/photo_detection.h"

namespace layerlab {

inline constexpr size_t kMinIntrinsicsViews = 3;
inline constexpr double kMaxFocalLengthRelativeStd = 0.02;

struct BoardView {
  std::string photo;
  std::vector<std::array<double, 2>> corners;  // camera pixels, row by row as FindPrintedChessboard gives them
  double rms_px = 0;                           // its reprojection error in the estimate
  double tilt_rad = 0;                         // the board's tilt from face-on, as estimated
};

struct IntrinsicsEstimate {
  CameraIntrinsics camera;  // with its uncertainty
  int width = 0, height = 0;
  std::vector<BoardView> views;        // the photographs used
  std::vector<PhotoFailure> failures;  // the photographs not used, each with its reason
};

// The photographs of `plan` in `folder`. Throws layerlab::Error as above.
IntrinsicsEstimate EstimateIntrinsics(const std::string& folder, const CameraCapturePlan& plan,
                                      const PhotoCheck& check = {});

// The calibration of views whose corners are already found (their photographs `width` x `height`).
IntrinsicsEstimate CalibrateFromViews(const PrintedChessboard& board, std::vector<BoardView> views, int width,
                                      int height);

}  // namespace layerlab
