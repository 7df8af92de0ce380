// Closed-form checks on a panel's markers before the fit: how many distinct
// pixels they show and whether they lie on one line, and the best similarity
// (rotation, uniform scale, shift) from panel to image with and without a
// mirror, which tells a panel mounted the other way round.
#pragma once

#include <complex>
#include <vector>

namespace layerlab {

using Point2 = std::complex<double>;

struct PointSpread {
  int distinct = 0;       // points more than 1e-9 apart
  bool collinear = true;  // true also for fewer than three distinct points
};
PointSpread Spread(const std::vector<Point2>& points);

// The least-squares q = a p + b over pairs (p_i, q_i), and its RMS residual
// |q_i - a p_i - b|. Needs two distinct p.
struct Similarity {
  Point2 a, b;
  double rms = 0;
};
Similarity FitSimilarity(const std::vector<Point2>& from, const std::vector<Point2>& to);

}  // namespace layerlab
