#include "layerlab/targets/plane_wave_table.h"

#include <cmath>

#include "layerlab/targets/fast_cos.h"

namespace layerlab {

PlaneWaveTable::PlaneWaveTable(const PlaneWaves& waves, double plane_depth_m, std::array<double, 2> plane_center_m,
                               double origin_depth_m)
    : waves_(waves), scale_(plane_depth_m / origin_depth_m), center_m_(plane_center_m) {}

void PlaneWaveTable::SetPoints(std::span<const std::array<double, 2>> points_m) {
  const size_t n = waves_.kx.size();
  point_.resize(points_m.size() * 2 * n);
  const double *kx = waves_.kx.data(), *ky = waves_.ky.data();
  for (size_t i = 0; i < points_m.size(); ++i) {
    const double x = scale_ * points_m[i][0], y = scale_ * points_m[i][1];
    double* cos_q = point_.data() + i * 2 * n;
    double* sin_q = cos_q + n;
#pragma omp simd
    for (size_t k = 0; k < n; ++k) {
      const double q = kx[k] * x + ky[k] * y;
      cos_q[k] = FastCos(q);
      sin_q[k] = FastSin(q);
    }
  }
}

void PlaneWaveTable::PhasesOfView(double vx_m, double vy_m, ViewPhases* phases) const {
  const size_t n = waves_.kx.size();
  phases->resize(2 * n);
  const double sx = vx_m * (1 - scale_) - center_m_[0], sy = vy_m * (1 - scale_) - center_m_[1];
  for (size_t k = 0; k < n; ++k) {
    const double p = waves_.kx[k] * sx + waves_.ky[k] * sy + waves_.phase[k];
    (*phases)[k] = std::cos(p);
    (*phases)[n + k] = std::sin(p);
  }
}

double PlaneWaveTable::Value(size_t i, const ViewPhases& phases) const {
  const size_t n = waves_.kx.size();
  const double *cos_q = point_.data() + i * 2 * n, *sin_q = cos_q + n;
  const double *cos_p = phases.data(), *sin_p = cos_p + n;
  double sum = 0;
#pragma omp simd reduction(+ : sum)
  for (size_t k = 0; k < n; ++k) sum += cos_p[k] * cos_q[k] - sin_p[k] * sin_q[k];
  return waves_.Clamped(sum);
}

}  // namespace layerlab
