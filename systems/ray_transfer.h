// Paraxial ray transfer (ABCD) matrices: the one optics model of layerlab.
//
// A ray is (height y, slope u = dy/dz) on one transverse axis, in the optical
// path unfolded from the pupil outward (a fold mirror's reversal of one axis
// is kept apart, as a flag: see systems/optical_path.h). An element maps it by
//   (y', u') = (A y + B u, C y + D u):
//   free space of length t:          A = 1, B = t, C = 0, D = 1
//   thin lens or mirror of power P:  A = 1, B = 0, C = -P, D = 1   (P = 1/f; a
//                                    concave mirror converges: P = 2/R > 0)
// The transfer from the pupil plane to a panel, M = T(t_n) L(P_n) ... L(P_1) T(t_1),
// sends the ray leaving pupil point x with slope u to the panel point
// A x + B u. A panel point is seen from the eye as the image plane where every
// ray through it would have to come from: A x + B u = A (x + (B/A) u), so
//   image depth z = B / A from the pupil, D = A / B diopters (0 when A = 0),
//   lateral magnification 1 / A (negative: inverted by a real intermediate image),
//   tan-angle per meter of panel seen from the pupil center: 1 / B.
// D and 1/B stay finite at A = 0 (the image at infinity). B = 0 means the panel
// is imaged into the pupil plane, which no eye can see.
//
// Templated on the scalar so that the compile (double) and the calibration's
// Ceres cost functions (ceres::Jet) share the same composition.
#pragma once

#include <cmath>
#include <limits>

namespace layerlab {

// True when `value`, a sum of terms no larger than `scale`, is zero to within
// its rounding: a transfer's `a` there means the image is at infinity (0 D),
// which rounding would otherwise turn into +-1e-16 D.
inline bool ZeroWithinRounding(double value, double scale) {
  return std::abs(value) <= 8 * std::numeric_limits<double>::epsilon() * scale;
}

template <typename T>
struct RayTransfer {
  T a = T(1), b = T(0), c = T(0), d = T(1);

  // This transfer followed by free space of length t (toward the panels).
  RayTransfer then_gap(const T& t) const { return {a + t * c, b + t * d, c, d}; }
  // This transfer followed by a thin element of power p (1/m).
  RayTransfer then_power(const T& p) const { return {a, b, c - p * a, d - p * b}; }
  // This transfer followed by `next`.
  RayTransfer then(const RayTransfer& n) const {
    return {n.a * a + n.b * c, n.a * b + n.b * d, n.c * a + n.d * c, n.c * b + n.d * d};
  }

  // Where this transfer (pupil -> a plane) puts that plane's image, seen from the eye.
  T diopters() const { return a / b; }
  T tan_per_meter() const { return T(1) / b; }
  T magnification() const { return T(1) / a; }
};

// The free-space length t after `before` at which the image lands at `diopters`
// (a + t c = D (b + t d)); `solvable` is false when no length does (the
// element before already fixes the image's depth: c = D d).
template <typename T>
T GapForDiopters(const RayTransfer<T>& before, const T& diopters, bool* solvable) {
  const T denominator = before.c - diopters * before.d;
  *solvable = denominator != T(0);
  if (!*solvable) return T(0);
  return (diopters * before.b - before.a) / denominator;
}

}  // namespace layerlab
