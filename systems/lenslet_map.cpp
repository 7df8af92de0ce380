#include "layerlab/systems/lenslet_map.h"

#include <cmath>
#include <limits>

namespace layerlab {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

}  // namespace

LensletMap::LensletMap(const LensArraySpec& array, double a1, double b1, double diopters, double shift_per_m,
                       double crosstalk_free_m)
    : array_(array),
      a1_(a1),
      b1_(b1),
      diopters_(diopters),
      shift_per_m_(shift_per_m),
      crosstalk_free_m_(crosstalk_free_m) {}

double LensletMap::AxisCentre(double h, int count) const {
  const double w = array_.pitch_m;
  const double i = std::floor(h / w + 0.5 * count);  // lenslet i spans [(i - count/2) w, (i + 1 - count/2) w)
  if (!(i >= 0 && i < count)) return kNaN;
  const double centre = (i + 0.5 - 0.5 * count) * w;
  return std::abs(h - centre) <= 0.5 * array_.fill * w ? centre : kNaN;
}

std::array<double, 2> LensletMap::LensletCentre(double h_x, double h_y) const {
  if (!array_.hexagonal) return {AxisCentre(h_x, array_.cols), AxisCentre(h_y, array_.rows)};
  // Rows of centres sqrt(3)/2 w apart, the odd ones shifted by w/2: the nearest centre is in one of the two rows
  // around h_y; it lies in the cell (a hexagon) whose inner radius is w/2, scaled by the fill factor.
  const double w = array_.pitch_m, row_step = 0.5 * std::sqrt(3.0) * w;
  std::array<double, 2> best{kNaN, kNaN};
  double best_d2 = std::numeric_limits<double>::infinity();
  const double r0 = std::floor(h_y / row_step + 0.5 * (array_.rows - 1));
  for (double r : {r0, r0 + 1}) {
    if (!(r >= 0 && r < array_.rows)) continue;
    const double shift = std::fmod(r, 2.0) == 1 ? 0.5 * w : 0.0;
    const double i = std::round((h_x - shift) / w + 0.5 * (array_.cols - 1));
    if (!(i >= 0 && i < array_.cols)) continue;
    const double cx = (i - 0.5 * (array_.cols - 1)) * w + shift, cy = (r - 0.5 * (array_.rows - 1)) * row_step;
    const double d2 = (h_x - cx) * (h_x - cx) + (h_y - cy) * (h_y - cy);
    if (d2 < best_d2) best_d2 = d2, best = {cx, cy};
  }
  if (std::isnan(best[0])) return best;
  const double dx = h_x - best[0], dy = h_y - best[1], reach = 0.5 * array_.fill * w;
  const double half = 0.5, across = 0.5 * std::sqrt(3.0);  // the cell's three edge normals: (1, 0), (1/2, +-sqrt3/2)
  if (std::abs(dx) > reach || std::abs(half * dx + across * dy) > reach || std::abs(half * dx - across * dy) > reach)
    return {kNaN, kNaN};
  return best;
}

double LensletMap::ShiftX(double p_x, double U_x) const {
  return U_x + shift_per_m_ * AxisCentre(a1_ * p_x + b1_ * (U_x - diopters_ * p_x), array_.cols);
}

double LensletMap::ShiftY(double p_y, double U_y) const {
  return U_y + shift_per_m_ * AxisCentre(a1_ * p_y + b1_ * (U_y - diopters_ * p_y), array_.rows);
}

std::array<double, 2> LensletMap::Shift(double p_x, double p_y, double U_x, double U_y) const {
  const std::array<double, 2> c =
      LensletCentre(a1_ * p_x + b1_ * (U_x - diopters_ * p_x), a1_ * p_y + b1_ * (U_y - diopters_ * p_y));
  return {U_x + shift_per_m_ * c[0], U_y + shift_per_m_ * c[1]};
}

}  // namespace layerlab
