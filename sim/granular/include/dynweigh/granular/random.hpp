#pragma once
// Deterministic random numbers for the granular models.
// The standard distributions (std::uniform_*_distribution, std::normal_distribution) are
// implementation-defined, so the same seed would give different runs on different standard
// libraries; these generators are bit-identical everywhere.
#include <cstdint>

namespace dynweigh::granular {

// SplitMix64 (Steele, Lea & Flood 2014): used only to expand one seed into a full state.
class SplitMix64 {
 public:
  explicit SplitMix64(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
  }

 private:
  std::uint64_t state_;
};

// xoshiro256** (Blackman & Vigna 2018): fast, small state, good statistical quality.
class Random {
 public:
  explicit Random(std::uint64_t seed = 1) {
    SplitMix64 expand(seed);
    for (auto& word : state_) word = expand.next();
  }

  std::uint64_t next_u64() {
    const std::uint64_t result = rotl(state_[1] * 5, 7) * 9;
    const std::uint64_t t = state_[1] << 17;
    state_[2] ^= state_[0];
    state_[3] ^= state_[1];
    state_[1] ^= state_[2];
    state_[0] ^= state_[3];
    state_[2] ^= t;
    state_[3] = rotl(state_[3], 45);
    return result;
  }

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
  static std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
  std::uint64_t state_[4];
};

}  // namespace dynweigh::granular
