// Random numbers that are the same on every machine and in every thread
// order: SplitMix64 (Steele, Lea and Flood 2014), seeded per use, with our own
// uniform doubles (the standard distributions differ between libraries).
#pragma once

#include <cmath>
#include <cstdint>
#include <numbers>

namespace layerlab {

class SplitMix64 {
 public:
  explicit SplitMix64(uint64_t seed) : state_(seed) {}
  uint64_t next() {
    uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  // In [0, 1), 53 random bits.
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }

 private:
  uint64_t state_;
};

// Standard normal numbers (Box-Muller) from SplitMix64.
class Gaussian {
 public:
  explicit Gaussian(uint64_t seed) : random_(seed) {}
  double uniform() { return random_.uniform(); }
  double operator()() {
    const double u = 1.0 - random_.uniform(), v = random_.uniform();
    return std::sqrt(-2.0 * std::log(u)) * std::cos(2.0 * std::numbers::pi * v);
  }

 private:
  SplitMix64 random_;
};

// A seed for one item of a keyed family (view, row, ...): hashes key into seed.
inline uint64_t MixSeed(uint64_t seed, uint64_t key) { return SplitMix64(seed ^ (key * 0xD1B54A32D192ED03ull)).next(); }

}  // namespace layerlab
