// cos(x) and sin(x) without a library call, so that loops over many sinusoids (noise
// textures) vectorize: reduction to [-pi, pi] by rounding x / 2pi, then the
// even Taylor polynomial of degree 22 (error below 1e-11 on [-pi, pi]; the
// reduction adds about |x| * 1e-16).
#pragma once

namespace layerlab {

inline double FastCos(double x) {
  constexpr double kInvTwoPi = 0.15915494309189533577;
  constexpr double kTwoPiHi = 6.28318530717958623200, kTwoPiLo = 2.44929359829470635445e-16;
  // Round to nearest by the 1.5 * 2^52 trick (no rounding call, so it vectorizes).
  constexpr double kRound = 6755399441055744.0;
  double n = (x * kInvTwoPi + kRound) - kRound;
  double r = (x - n * kTwoPiHi) - n * kTwoPiLo;
  double r2 = r * r;
  // 1 - r^2/2! + r^4/4! - ... - r^22/22!, Horner in r^2.
  double p = -8.8967913924505732867e-22;
  p = p * r2 + 4.1103176233121648585e-19;
  p = p * r2 - 1.5619206968586226462e-16;
  p = p * r2 + 4.7794773323873852974e-14;
  p = p * r2 - 1.1470745597729724714e-11;
  p = p * r2 + 2.0876756987868098979e-09;
  p = p * r2 - 2.7557319223985890653e-07;
  p = p * r2 + 2.4801587301587301587e-05;
  p = p * r2 - 1.3888888888888888889e-03;
  p = p * r2 + 4.1666666666666666667e-02;
  p = p * r2 - 0.5;
  return p * r2 + 1.0;
}

// sin(x) = cos(x - pi/2); the shift adds about |x| * 1e-16.
inline double FastSin(double x) {
  constexpr double kHalfPi = 1.57079632679489661923;
  return FastCos(x - kHalfPi);
}

}  // namespace layerlab
