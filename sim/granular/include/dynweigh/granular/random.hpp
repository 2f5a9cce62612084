#pragma once
// Deterministic random numbers for the granular models: the project's generator
// (sim/random.hpp, xoshiro256** seeded by SplitMix64, bit-identical on every standard library) with
// the draws these models need.
#include <cstdint>

#include "dynweigh/sim/random.hpp"

namespace dynweigh::granular {

class Random {
 public:
  explicit Random(std::uint64_t seed = 1) : core_(seed) {}

  std::uint64_t next_u64() { return core_.next_u64(); }

  // Uniform in [0, 1) with 53 random bits.
  double uniform01() { return static_cast<double>(next_u64() >> 11) * 0x1.0p-53; }
  double uniform(double low, double high) { return low + (high - low) * uniform01(); }

  // Uniform integer in [0, bound), unbiased: draws below 2^64 mod bound are rejected so every
  // residue is equally likely.
  std::uint64_t below(std::uint64_t bound) {
    if (bound == 0) return 0;
    const std::uint64_t reject_below = (0 - bound) % bound;
    for (;;) {
      const std::uint64_t draw = next_u64();
      if (draw >= reject_below) return draw % bound;
    }
  }

 private:
  sim::Random core_;
};

}  // namespace dynweigh::granular
