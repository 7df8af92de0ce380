#include "layerlab/calibration/similarity_fit.h"

#include <cmath>

namespace layerlab {
namespace {

Point2 Mean(const std::vector<Point2>& points) {
  Point2 sum = 0;
  for (const Point2& p : points) sum += p;
  return sum / static_cast<double>(points.size());
}

}  // namespace

PointSpread Spread(const std::vector<Point2>& points) {
  PointSpread spread;
  std::vector<Point2> distinct;
  for (const Point2& p : points) {
    bool seen = false;
    for (const Point2& d : distinct) seen = seen || std::abs(p - d) <= 1e-9;
    if (!seen) distinct.push_back(p);
  }
  spread.distinct = static_cast<int>(distinct.size());
  if (distinct.size() < 3) return spread;
  // Collinear when the scatter matrix has no second direction: its smaller
  // eigenvalue, relative to the larger, vanishes.
  const Point2 mean = Mean(distinct);
  double sxx = 0, syy = 0, sxy = 0;
  for (const Point2& p : distinct) {
    const Point2 d = p - mean;
    sxx += d.real() * d.real(), syy += d.imag() * d.imag(), sxy += d.real() * d.imag();
  }
  const double half_trace = 0.5 * (sxx + syy);
  const double root = std::sqrt(0.25 * (sxx - syy) * (sxx - syy) + sxy * sxy);
  spread.collinear = half_trace - root <= 1e-12 * (half_trace + root);
  return spread;
}

Similarity FitSimilarity(const std::vector<Point2>& from, const std::vector<Point2>& to) {
  const Point2 from_mean = Mean(from), to_mean = Mean(to);
  Point2 cross = 0;
  double spread = 0;
  for (size_t i = 0; i < from.size(); ++i) {
    cross += (to[i] - to_mean) * std::conj(from[i] - from_mean);
    spread += std::norm(from[i] - from_mean);
  }
  Similarity s;
  s.a = cross / spread;
  s.b = to_mean - s.a * from_mean;
  double sum = 0;
  for (size_t i = 0; i < from.size(); ++i) sum += std::norm(to[i] - s.a * from[i] - s.b);
  s.rms = std::sqrt(sum / static_cast<double>(from.size()));
  return s;
}

}  // namespace layerlab
