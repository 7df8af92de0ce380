#include "layerlab/calibration/detection_noise.h"

#include <algorithm>
#include <cmath>
#include <set>

#include <Eigen/Dense>

namespace layerlab {

std::optional<DetectionNoise> EstimateBoardNoise(const std::vector<MarkerObservation>& markers) {
  const int n = static_cast<int>(markers.size());
  if (n < kBoardNoiseMinMarkers) return std::nullopt;
  std::set<double> cols, rows;
  double col_min = INFINITY, col_max = -INFINITY, row_min = INFINITY, row_max = -INFINITY;
  for (const MarkerObservation& m : markers) {
    cols.insert(m.col), rows.insert(m.row);
    col_min = std::min(col_min, m.col), col_max = std::max(col_max, m.col);
    row_min = std::min(row_min, m.row), row_max = std::max(row_max, m.row);
  }
  // A cubic along an axis needs four distinct values on it.
  if (cols.size() < 4 || rows.size() < 4) return std::nullopt;
  // Centered and scaled to [-1, 1], so that the monomials are of one size.
  const double col_mid = 0.5 * (col_min + col_max), col_half = 0.5 * (col_max - col_min);
  const double row_mid = 0.5 * (row_min + row_max), row_half = 0.5 * (row_max - row_min);
  Eigen::MatrixXd design(n, kBoardNoiseTerms);
  Eigen::MatrixXd angles(n, 2);
  for (int i = 0; i < n; ++i) {
    const double s = (markers[i].col - col_mid) / col_half, t = (markers[i].row - row_mid) / row_half;
    int term = 0;
    for (int degree = 0; degree <= 3; ++degree)
      for (int power_t = 0; power_t <= degree; ++power_t)
        design(i, term++) = std::pow(s, degree - power_t) * std::pow(t, power_t);
    angles(i, 0) = markers[i].angle_x;
    angles(i, 1) = markers[i].angle_y;
  }
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(design);
  if (qr.rank() < kBoardNoiseTerms) return std::nullopt;
  const Eigen::MatrixXd residual = angles - design * qr.solve(angles);
  DetectionNoise noise;
  noise.degrees_of_freedom = 2 * (n - kBoardNoiseTerms);
  noise.sigma_rad = std::sqrt(residual.squaredNorm() / noise.degrees_of_freedom);
  return noise;
}

}  // namespace layerlab
