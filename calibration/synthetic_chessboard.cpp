#include "layerlab/calibration/synthetic_chessboard.h"

#include <cmath>
#include <cstdint>

#include "layerlab/framework/error.h"

namespace layerlab {
namespace {

using Vec3 = std::array<double, 3>;

double Dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3 Cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

}  // namespace

BoardPose PoseOfPlannedPhoto(const PlannedBoardPhoto& photo, const PrintedChessboard& board,
                             const PhotoCamera& camera) {
  const CameraIntrinsics& k = camera.intrinsics;
  // Pixel centers are integers: the frame spans -0.5 to width - 0.5.
  const auto angle = AngleFromCameraPixel(k, photo.center_in_frame[0] * camera.width - 0.5,
                                          photo.center_in_frame[1] * camera.height - 0.5);
  if (!angle) throw Error(photo.photo + ": the planned place in the frame lies beyond the camera's distortion");
  const double depth = k.fx * board.squares_x * board.square_m / (photo.width_in_frame * camera.width);
  BoardPose pose;
  pose.center_m = {depth * std::tan((*angle)[0]), -depth * std::tan((*angle)[1]), depth};
  // About the horizontal axis (top edge away), then about the vertical axis (right edge away).
  const double a = photo.tilt_rad[0], b = photo.tilt_rad[1];
  pose.across = {std::cos(b), 0, std::sin(b)};
  pose.down = {std::sin(a) * std::sin(b), std::cos(a), -std::sin(a) * std::cos(b)};
  return pose;
}

std::array<double, 3> BoardCorner(const PrintedChessboard& board, const BoardPose& pose, int a, int b) {
  const double x = (a + 1 - 0.5 * board.squares_x) * board.square_m;
  const double y = (b + 1 - 0.5 * board.squares_y) * board.square_m;
  Vec3 p;
  for (int i = 0; i < 3; ++i) p[i] = pose.center_m[i] + x * pose.across[i] + y * pose.down[i];
  return p;
}

BoardPhotoRenderer::BoardPhotoRenderer(const PhotoCamera& camera) : camera_(camera) {
  CheckPhotoCamera(camera);
  slopes_ = PixelCornerSlopes(camera);
}

Image BoardPhotoRenderer::Render(const PrintedChessboard& board, const BoardPose& pose, uint64_t seed_key,
                                 const BoardScene& scene) const {
  if (!(scene.paper > 0) || !(scene.ink >= 0) || !(scene.surroundings >= 0) || !std::isfinite(scene.paper) ||
      !std::isfinite(scene.ink) || !std::isfinite(scene.surroundings))
    throw Error("the board's paper must reflect some light, and no reflectance may be negative or infinite");
  const Vec3 normal = Cross(pose.across, pose.down);
  const double s = board.square_m, half_x = 0.5 * board.squares_x * s, half_y = 0.5 * board.squares_y * s;
  const double gain = camera_.white / scene.paper;
  // A ray from the aperture (x right, y up in the eye's convention) is, in camera coordinates, o = (x, -y, 0)
  // along d = (t_x, -t_y, 1); it meets the board's plane where normal . (o + t d - center) = 0.
  auto light = [&](const std::array<double, 2>& aperture_point, const std::array<double, 2>& slope) {
    const Vec3 o = {aperture_point[0], -aperture_point[1], 0}, d = {slope[0], -slope[1], 1};
    const double along = Dot(normal, d);
    const Vec3 to_center = {pose.center_m[0] - o[0], pose.center_m[1] - o[1], pose.center_m[2] - o[2]};
    const double t = along != 0 ? Dot(normal, to_center) / along : -1;
    if (!(t > 0)) return gain * scene.surroundings;
    const Vec3 rel = {o[0] + t * d[0] - pose.center_m[0], o[1] + t * d[1] - pose.center_m[1],
                      o[2] + t * d[2] - pose.center_m[2]};
    const double i = std::floor((Dot(pose.across, rel) + half_x) / s);
    const double j = std::floor((Dot(pose.down, rel) + half_y) / s);
    // Off the paper (a ray grazing the plane gives NaN here, off it too).
    if (!(i >= -1 && j >= -1 && i <= board.squares_x && j <= board.squares_y)) return gain * scene.surroundings;
    const bool inside = i >= 0 && j >= 0 && i < board.squares_x && j < board.squares_y;
    const bool dark = inside && (static_cast<int64_t>(i + j) & 1) == 0;
    return gain * (dark ? scene.ink : scene.paper);
  };
  return RecordOnSensor(camera_, PixelSignals(camera_, slopes_, seed_key, light), seed_key);
}

}  // namespace layerlab
