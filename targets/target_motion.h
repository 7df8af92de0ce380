// Moving target scenes: a mesh's placement and the camera keyed over time
// (docs/target-format.md, "Moving scenes"). Between two keys a position and
// each rotation angle go linearly; before the first key and after the last
// they hold. A key may give a position, a rotation or both; a channel no key
// gives stays where the object's own "position" or "rotation" puts it.
#pragma once

#include <array>
#include <optional>
#include <vector>

namespace layerlab {

using Vec3 = std::array<double, 3>;

struct MotionKey {
  double time_s = 0;                 // s
  std::optional<Vec3> position_m;    // m, eye space
  std::optional<Vec3> rotation_rad;  // rad, about x, then y, then z
};

// The value of a channel at `time_s` over the keys that give it (in time order), else `fallback`.
Vec3 PositionAt(const std::vector<MotionKey>& keys, double time_s, const Vec3& fallback);
Vec3 RotationAt(const std::vector<MotionKey>& keys, double time_s, const Vec3& fallback);

// Rotation about x, then y, then z (eye-space axes): R = Rz Ry Rx.
std::array<Vec3, 3> RotationMatrix(const Vec3& angles_rad);

// p = position + R q for each vertex q of `local_m`.
void PlaceVertices(const std::vector<Vec3>& local_m, const Vec3& position_m, const Vec3& rotation_rad,
                   std::vector<Vec3>* placed_m);

// A mesh that moves: its vertices scaled but not placed (m), its placement in the file, and its keys.
struct MeshMotion {
  std::vector<Vec3> local_m;
  Vec3 position_m{}, rotation_rad{};
  std::vector<MotionKey> keys;
};

// A scene's "animation": its frame rate and the camera's keyed position (the whole scene is seen from it).
struct TargetAnimation {
  double frame_rate_hz = 30;      // Hz
  std::vector<MotionKey> camera;  // positions only
};

}  // namespace layerlab
