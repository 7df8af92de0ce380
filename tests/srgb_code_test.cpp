// The sRGB codes by table equal those of the pow expression: at every code
// step and its neighbours, at the table's own step edges, and at random values.
#include "layerlab/framework/srgb_code.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>

namespace layerlab {
namespace {

double Next(double v, int ulps) {
  for (; ulps > 0; --ulps) v = std::nextafter(v, 2.0);
  for (; ulps < 0; ++ulps) v = std::nextafter(v, -1.0);
  return v;
}

TEST(SrgbCode, EqualsTheExpressionAtEveryStepAndItsNeighbours) {
  // The step to code c, found here by the expression alone (bisection over values, then walked to the last ulp).
  int steps = 0;
  for (int c = 1; c <= 255; ++c) {
    double lo = 0, hi = 1;
    for (int n = 0; n < 200; ++n) {
      const double mid = 0.5 * (lo + hi);
      (SrgbCodeByFormula(mid) >= c ? hi : lo) = mid;
    }
    while (SrgbCodeByFormula(std::nextafter(hi, -1.0)) >= c) hi = std::nextafter(hi, -1.0);
    ASSERT_EQ(SrgbCodeByFormula(hi), c);
    ASSERT_EQ(SrgbCodeByFormula(std::nextafter(hi, -1.0)), c - 1);
    double v = Next(hi, -2000);
    for (int u = -2000; u <= 2000; ++u, v = std::nextafter(v, 2.0))
      ASSERT_EQ(SrgbCode(v), SrgbCodeByFormula(v)) << "code " << c << ", " << u << " ulps from its step: " << v;
    ++steps;
  }
  EXPECT_EQ(steps, 255);
}

TEST(SrgbCode, EqualsTheExpressionAtTheTableEdgesAndOutsideTheRange) {
  for (int s = 0; s <= 65536; ++s)
    for (int u = -3; u <= 3; ++u) {
      const double v = Next(s / 65536.0, u);
      ASSERT_EQ(SrgbCode(v), SrgbCodeByFormula(v)) << v;
    }
  for (double v :
       {-1.0, -0.0, 0.0, std::numeric_limits<double>::denorm_min(), 1e-300, 0.0031308, 1.0, std::nextafter(1.0, 2.0),
        1e300, std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(), std::nan("")})
    EXPECT_EQ(SrgbCode(v), SrgbCodeByFormula(v)) << v;
  EXPECT_EQ(SrgbCode(std::nan("")), 0);
  EXPECT_EQ(SrgbCode(2.0), 255);
  EXPECT_EQ(SrgbCode(0.5), 188);  // 255 (1.055 0.5^(1/2.4) - 0.055) = 187.52
}

TEST(SrgbCode, EqualsTheExpressionAtRandomValues) {
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> wide(-0.1, 1.1), low(0, 0.01);
  for (int n = 0; n < 2000000; ++n) {
    const double v = n % 4 == 0 ? low(rng) : wide(rng);
    ASSERT_EQ(SrgbCode(v), SrgbCodeByFormula(v)) << v;
    const double f = static_cast<float>(v) / 0.7;  // a float divided by a white, as WriteSrgbPng makes them
    ASSERT_EQ(SrgbCode(f), SrgbCodeByFormula(f)) << f;
  }
}

}  // namespace
}  // namespace layerlab
