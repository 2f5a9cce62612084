#pragma once
// Running statistics of avalanches: means of size, area and duration, and a log-binned size
// histogram from which the exponent tau_s of P(s) ~ s^-tau_s is estimated.
#include <array>
#include <cstdint>

#include "dynweigh/granular/avalanche.hpp"

namespace dynweigh::granular {

class AvalancheStatistics {
 public:
  static constexpr int kSizeBins = 48;  // bin b holds sizes in [2^b, 2^(b+1))

  void record(const Avalanche& avalanche);

  std::int64_t grains() const { return grains_; }          // grains recorded (with or without avalanche)
  std::int64_t avalanches() const { return avalanches_; }  // grains that caused a toppling
  double mean_topplings_per_grain() const;
  double mean_size() const;      // over avalanches only
  double mean_area() const;
  double mean_duration() const;
  std::int64_t largest_size() const { return largest_size_; }
  std::int64_t size_histogram(int bin) const { return size_histogram_[static_cast<std::size_t>(bin)]; }

  // Least-squares slope of log P(s) against log s over the log bins between min_size and
  // max_size (bins with fewer than 10 avalanches are left out). Returns 0 without enough bins.
  double estimate_tau_s(std::int64_t min_size, std::int64_t max_size) const;

 private:
  std::int64_t grains_ = 0;
  std::int64_t avalanches_ = 0;
  double size_sum_ = 0;
  double area_sum_ = 0;
  double duration_sum_ = 0;
  std::int64_t largest_size_ = 0;
  std::array<std::int64_t, kSizeBins> size_histogram_{};
};

}  // namespace dynweigh::granular
