// Behind a lens array (elements/lens_array.cpp): which lenslet an eye ray
// passes, and where it then reads the panel behind the array.
//
// The layer's paraxial image (its depth, pitch and grid, VirtualLayer) is the
// one formed through a lenslet centred on the axis. A ray through lenslet i,
// centred at c_i in the array's plane, leaves it deviated by P c_i more than
// through that one (a thin lens of power P centred at c_i: u' = u - P (h - c_i)),
// which moves the point where it meets the panel by b2 P c_i (b2: the B of the
// path from the array to the panel) and its tan-angle on the layer's grid by
//   k c_i,   k = b2 P / B                (B: the layer's pupil-to-panel B).
// Ray (p, U), U = u + D p on the layer's grid (layer_sampler.h), meets the
// array at h = a1 p + b1 (U - D p), (a1, b1) the path up to the array. A ray
// that meets the array between the lenslets' clear apertures (fill factor
// below 1) or beyond the array is lost (NaN, which reads no pixel).
//
// What it leaves to the eye: rays through lenslet i may meet the panel beyond
// lenslet i's elemental image, in its neighbour's (crosstalk, read as the
// panel shows it; the light field and the retinal images have it), and
// nothing blocks them (no baffles between the lenslets).
#pragma once

#include <array>

#include "layerlab/elements/element.h"

namespace layerlab {

class LensletMap {
 public:
  // (a1, b1): pupil to the array; `diopters`: the layer's D; `shift_per_m`: k above; `crosstalk_free_m`: the
  // span of pupil points (m) whose rays through each lenslet meet only its own elemental image (compile.cpp).
  LensletMap(const LensArraySpec& array, double a1, double b1, double diopters, double shift_per_m,
             double crosstalk_free_m);

  // The square lattice's columns depend on x alone and its rows on y alone.
  bool separable() const { return !array_.hexagonal; }
  double ShiftX(double p_x, double U_x) const;  // separable() only
  double ShiftY(double p_y, double U_y) const;  // separable() only
  std::array<double, 2> Shift(double p_x, double p_y, double U_x, double U_y) const;

  // The centre of the lenslet that point h (m, in the array's plane) lies in; NaN outside every clear aperture.
  std::array<double, 2> LensletCentre(double h_x, double h_y) const;
  const LensArraySpec& array() const { return array_; }
  double crosstalk_free_m() const { return crosstalk_free_m_; }

 private:
  double AxisCentre(double h, int count) const;  // square lattice, one axis

  LensArraySpec array_;
  double a1_, b1_, diopters_, shift_per_m_, crosstalk_free_m_;
};

}  // namespace layerlab
