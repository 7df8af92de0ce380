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

// [pixel][rgb] as [pixel][rgb, 0].
inline void PadRgb(const std::vector<float>& rgb, std::vector<Rgb4>* out) {
  const size_t n = rgb.size() / 3;
  out->resize(n);
  for (size_t k = 0; k < n; ++k) (*out)[k] = LoadRgb(&rgb[k * 3]);
}

}  // namespace layerlab
