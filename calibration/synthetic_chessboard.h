// Synthetic photographs of a printed chessboard (camera_capture_plan.h), for
// the tests and for estimating intrinsics without a camera at hand: a flat
// board of known square size at a known pose, seen through the synthetic
// camera (photo_camera.h: distortion, aperture and focus, supersampling, blur,
// photon and read noise, response, bits).
//
// Camera coordinates follow camera_model.h's pixels: x right, y down, z along
// the view. The paper reflects `paper` (the board's white squares and its one
// square of margin), the ink `ink`, and what lies around the paper
// `surroundings`; the camera's `white` is the signal of the paper at exposure 1.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "layerlab/calibration/camera_capture_plan.h"
#include "layerlab/calibration/photo_camera.h"
#include "layerlab/framework/exr_image.h"

namespace layerlab {

// Where the board is: its center (the middle of its squares) in camera coordinates, m, and its axes (unit
// vectors in camera coordinates: across its squares toward its right edge, down toward its bottom edge). A point
// (X, Y) of the board, m from its center, lies at center + X across + Y down.
struct BoardPose {
  std::array<double, 3> center_m = {0, 0, 0.5};
  std::array<double, 3> across = {1, 0, 0}, down = {0, 1, 0};
};

// The pose a planned photograph asks for through `camera`: turned by its tilts (about the horizontal axis
// first, then about the vertical one), its center on the ray of the planned place in the frame, at the
// distance where its squares span the planned fraction of the frame's width.
BoardPose PoseOfPlannedPhoto(const PlannedBoardPhoto& photo, const PrintedChessboard& board, const PhotoCamera& camera);

// Inner corner (a, b) of the board (a across, b down from its top left), in camera coordinates, m.
std::array<double, 3> BoardCorner(const PrintedChessboard& board, const BoardPose& pose, int a, int b);

struct BoardScene {
  double paper = 0.9, ink = 0.05, surroundings = 0.3;  // reflectances
};

class BoardPhotoRenderer {
 public:
  explicit BoardPhotoRenderer(const PhotoCamera& camera);
  const PhotoCamera& camera() const { return camera_; }

  // One channel "Y"; `seed_key` picks the jitter and noise (MixSeed with the camera's seed).
  Image Render(const PrintedChessboard& board, const BoardPose& pose, uint64_t seed_key,
               const BoardScene& scene = {}) const;

 private:
  PhotoCamera camera_;
  std::vector<double> slopes_;
};

}  // namespace layerlab
