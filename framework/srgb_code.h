// Linear light to 8-bit sRGB codes (IEC 61966-2-1), for the PNGs people look at.
#pragma once

#include <cstdint>

namespace layerlab {

// The sRGB transfer function on [0, 1]: 12.92 v below 0.0031308, else 1.055 v^(1/2.4) - 0.055.
double SrgbEncode(double linear);

// The 8-bit code of a linear value, clamped to [0, 1] (NaN to 0):
// lround(255 SrgbEncode(v)) without a pow per value. The code steps at 255
// thresholds, found once from that same expression; a value is placed among
// them from a table over [0, 1] in steps finer than any two thresholds lie
// apart, then one comparison each way. The same codes as the expression
// (tests/srgb_code_test.cpp, every threshold and its neighbours).
uint8_t SrgbCode(double linear);

// The same by the expression itself, for the test.
uint8_t SrgbCodeByFormula(double linear);

}  // namespace layerlab
