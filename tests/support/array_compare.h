// Array comparisons for tests, in the spirit of Ceres' test_util.h: whole
// arrays element by element, bit for bit, or up to one common scale, each
// failing with the count of mismatches and the first one (index and values)
// instead of one failure line per element.
#pragma once

#include <cmath>
#include <cstring>
#include <span>
#include <sstream>
#include <string>
#include <type_traits>

#include <gtest/gtest.h>

namespace layerlab::testing {

namespace array_compare_detail {

template <class A, class B, class Bad>
::testing::AssertionResult Report(const A& actual, const B& expected, Bad bad, const std::string& what) {
  if (std::size(actual) != std::size(expected))
    return ::testing::AssertionFailure() << "sizes differ: " << std::size(actual) << " against " << std::size(expected);
  size_t mismatches = 0, first = 0;
  for (size_t i = 0; i < std::size(actual); ++i)
    if (bad(i) && mismatches++ == 0) first = i;
  if (mismatches == 0) return ::testing::AssertionSuccess();
  std::ostringstream s;
  s.precision(9);
  s << mismatches << " of " << std::size(actual) << " values differ " << what << "; the first at " << first << ": "
    << double(actual[first]) << " against " << double(expected[first]);
  return ::testing::AssertionFailure() << s.str();
}

}  // namespace array_compare_detail

// |actual[i] - expected[i]| <= max(abs_tol, rel_tol * |expected[i]|) for every i.
template <class A, class B>
::testing::AssertionResult ArraysNear(const A& actual, const B& expected, double rel_tol, double abs_tol = 0.0) {
  auto bad = [&](size_t i) {
    const double a = double(actual[i]), e = double(expected[i]);
    return !(std::abs(a - e) <= std::max(abs_tol, rel_tol * std::abs(e)));  // NaN is a mismatch
  };
  std::ostringstream what;
  what << "by more than max(" << abs_tol << ", " << rel_tol << " |expected|)";
  return array_compare_detail::Report(actual, expected, bad, what.str());
}

// The same bits in every element (+0 and -0 differ; NaNs of the same bits agree).
template <class A, class B>
::testing::AssertionResult ArraysSameBits(const A& actual, const B& expected) {
  static_assert(std::is_same_v<std::decay_t<decltype(actual[0])>, std::decay_t<decltype(expected[0])>>);
  auto bad = [&](size_t i) { return std::memcmp(&actual[i], &expected[i], sizeof(actual[i])) != 0; };
  return array_compare_detail::Report(actual, expected, bad, "in their bits");
}

// actual = s * expected for one s > 0 (the least-squares s = <a, e> / <e, e>),
// each element within rel_tol of the largest |s expected| (as Ceres'
// ExpectArraysCloseUpToScale). Fails when either array is all zeros and the
// other is not.
template <class A, class B>
::testing::AssertionResult ArraysNearUpToScale(const A& actual, const B& expected, double rel_tol) {
  if (std::size(actual) != std::size(expected))
    return ::testing::AssertionFailure() << "sizes differ: " << std::size(actual) << " against " << std::size(expected);
  double ae = 0, ee = 0, largest = 0;
  for (size_t i = 0; i < std::size(actual); ++i) {
    ae += double(actual[i]) * double(expected[i]);
    ee += double(expected[i]) * double(expected[i]);
  }
  const double s = ee > 0 ? ae / ee : 0;
  if (!(s > 0) && ae == 0 && ee == 0) return ArraysNear(actual, expected, 0.0, 0.0);  // both must be zeros
  if (!(s > 0)) return ::testing::AssertionFailure() << "no positive scale maps expected to actual (" << s << ")";
  for (size_t i = 0; i < std::size(expected); ++i) largest = std::max(largest, std::abs(s * double(expected[i])));
  auto bad = [&](size_t i) { return !(std::abs(double(actual[i]) - s * double(expected[i])) <= rel_tol * largest); };
  std::ostringstream what;
  what << "from " << s << " x expected by more than " << rel_tol << " of the largest";
  return array_compare_detail::Report(actual, expected, bad, what.str());
}

}  // namespace layerlab::testing
