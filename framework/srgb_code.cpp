#include "layerlab/framework/srgb_code.h"

#include <array>
#include <cmath>
#include <cstring>

namespace layerlab {

double SrgbEncode(double v) { return v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1 / 2.4) - 0.055; }

uint8_t SrgbCodeByFormula(double v) {
  v = v > 1 ? 1.0 : v > 0 ? v : 0.0;  // NaN lands on 0
  return static_cast<uint8_t>(std::lround(255 * SrgbEncode(v)));
}

namespace {

// 4096 steps over [0, 1]: the closest thresholds, in the linear part, lie 1 / (255 * 12.92) = 3.0e-4 apart.
constexpr int kSteps = 4096;

struct SrgbTable {
  std::array<double, 257> threshold;   // [c]: the least v with code >= c (c = 1..255); [0] 0, [256] above 1
  std::array<uint8_t, kSteps + 1> at;  // the code of step s's lower end, s / kSteps
  SrgbTable() {
    auto bits = [](double v) {
      uint64_t b;
      std::memcpy(&b, &v, sizeof b);
      return b;
    };
    auto value = [](uint64_t b) {
      double v;
      std::memcpy(&v, &b, sizeof v);
      return v;
    };
    threshold[0] = 0;
    for (int c = 1; c <= 255; ++c) {
      // Bisection over the bit patterns of [0, 1] (ordered like the values): code(lo) < c <= code(hi).
      uint64_t lo = bits(threshold[c - 1]), hi = bits(1.0);
      while (hi - lo > 1) {
        const uint64_t mid = lo + (hi - lo) / 2;
        (SrgbCodeByFormula(value(mid)) >= c ? hi : lo) = mid;
      }
      threshold[c] = value(hi);
    }
    threshold[256] = 2.0;
    for (int s = 0, c = 0; s <= kSteps; ++s) {
      const double v = double(s) / kSteps;
      while (c < 255 && v >= threshold[c + 1]) ++c;
      at[s] = static_cast<uint8_t>(c);
    }
  }
};

}  // namespace

uint8_t SrgbCode(double v) {
  static const SrgbTable table;
  v = v > 1 ? 1.0 : v > 0 ? v : 0.0;  // NaN lands on 0
  int c = table.at[static_cast<int>(v * kSteps)];
  // v * kSteps may round up to the next step: then c is one above, never more.
  if (v < table.threshold[c]) --c;
  if (v >= table.threshold[c + 1]) ++c;
  return static_cast<uint8_t>(c);
}

}  // namespace layerlab
