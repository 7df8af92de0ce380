// One RGB value in a 4-float vector (GCC and Clang vector extension: one SSE
// or NEON register), the fourth lane padding. The hot loops read and write a
// ray's three channels with one instruction each instead of three.
#pragma once

#include <cstring>
#include <vector>

namespace layerlab {

using Rgb4 = float __attribute__((vector_size(16)));

// Reads p[0..3]: p[3] must be readable (the next value's red, or padding); lane 3 is garbage.
inline Rgb4 LoadRgbOver(const float* p) {
  Rgb4 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

// Reads exactly p[0..2].
inline Rgb4 LoadRgb(const float* p) { return Rgb4{p[0], p[1], p[2], 0.0f}; }

inline void StoreRgb(const Rgb4& v, float* p) { p[0] = v[0], p[1] = v[1], p[2] = v[2]; }

// Sum over one row of rays of (target - light)^2, channels 0-2, in double.
// `target` is [ray][rgb]; all rays but the last read one float past their
// own unless `exact_last` is false (then the last does too). Two partial
// sums in named variables: one would make each ray wait for the last add,
// and an array indexed by ray parity would live in memory.
inline double SquaredErrorRow(const float* target, const Rgb4* light, int cols, bool exact_last) {
  using Double4 = double __attribute__((vector_size(32)));
  // acc += (t - l)^2; lane 3 sums whatever the padding lanes hold and is never
  // read. By reference: a 32-byte vector returned by value would change the
  // ABI between SSE and AVX builds.
  auto add_squared = [](Double4& acc, Rgb4 t, Rgb4 l) {
    const Double4 d = __builtin_convertvector(t, Double4) - __builtin_convertvector(l, Double4);
    acc += d * d;
  };
  Double4 even = {}, odd = {};
  const int safe = exact_last ? cols - 1 : cols;
  int j = 0;
  for (; j + 1 < safe; j += 2) {
    add_squared(even, LoadRgbOver(target + j * 3), light[j]);
    add_squared(odd, LoadRgbOver(target + j * 3 + 3), light[j + 1]);
  }
  for (; j < cols; ++j) add_squared(even, j < safe ? LoadRgbOver(target + j * 3) : LoadRgb(target + j * 3), light[j]);
  return (even[0] + odd[0]) + (even[1] + odd[1]) + (even[2] + odd[2]);
}

// [pixel][rgb] as [pixel][rgb, 0].
inline void PadRgb(const std::vector<float>& rgb, std::vector<Rgb4>* out) {
  const size_t n = rgb.size() / 3;
  out->resize(n);
  for (size_t k = 0; k < n; ++k) (*out)[k] = LoadRgb(&rgb[k * 3]);
}

}  // namespace layerlab
