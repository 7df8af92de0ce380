#include "layerlab/targets/target_motion.h"

#include <cmath>

namespace layerlab {
namespace {

template <typename Channel>
Vec3 ChannelAt(const std::vector<MotionKey>& keys, double time_s, const Vec3& fallback, Channel channel) {
  const MotionKey* before = nullptr;
  for (const MotionKey& key : keys) {
    const std::optional<Vec3>& value = channel(key);
    if (!value) continue;
    if (key.time_s >= time_s) {
      if (!before || key.time_s == time_s) return *value;
      const double w = (time_s - before->time_s) / (key.time_s - before->time_s);
      const Vec3& a = *channel(*before);
      return {a[0] + w * ((*value)[0] - a[0]), a[1] + w * ((*value)[1] - a[1]), a[2] + w * ((*value)[2] - a[2])};
    }
    before = &key;
  }
  return before ? *channel(*before) : fallback;
}

}  // namespace

Vec3 PositionAt(const std::vector<MotionKey>& keys, double time_s, const Vec3& fallback) {
  return ChannelAt(keys, time_s, fallback,
                   [](const MotionKey& k) -> const std::optional<Vec3>& { return k.position_m; });
}

Vec3 RotationAt(const std::vector<MotionKey>& keys, double time_s, const Vec3& fallback) {
  return ChannelAt(keys, time_s, fallback,
                   [](const MotionKey& k) -> const std::optional<Vec3>& { return k.rotation_rad; });
}

std::array<Vec3, 3> RotationMatrix(const Vec3& angles_rad) {
  const double cx = std::cos(angles_rad[0]), sx = std::sin(angles_rad[0]), cy = std::cos(angles_rad[1]),
               sy = std::sin(angles_rad[1]), cz = std::cos(angles_rad[2]), sz = std::sin(angles_rad[2]);
  return {{{cz * cy, cz * sy * sx - sz * cx, cz * sy * cx + sz * sx},
           {sz * cy, sz * sy * sx + cz * cx, sz * sy * cx - cz * sx},
           {-sy, cy * sx, cy * cx}}};
}

void PlaceVertices(const std::vector<Vec3>& local_m, const Vec3& position_m, const Vec3& rotation_rad,
                   std::vector<Vec3>* placed_m) {
  const std::array<Vec3, 3> r = RotationMatrix(rotation_rad);
  placed_m->resize(local_m.size());
  for (size_t i = 0; i < local_m.size(); ++i) {
    const Vec3& q = local_m[i];
    for (int row = 0; row < 3; ++row)
      (*placed_m)[i][row] = position_m[row] + r[row][0] * q[0] + r[row][1] * q[1] + r[row][2] * q[2];
  }
}

}  // namespace layerlab
