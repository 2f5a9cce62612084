#pragma once
// Stable-weight detection as industrial indicators do it: the filtered weight has stayed within a
// band for a while. Its mean over that while is the stable value.
#include <cstdint>

#include "dynweigh/firmware/compensated_sum.hpp"

namespace dynweigh::firmware {

class StableWeightDetector {
 public:
  void configure(float band, std::uint32_t samples) {
    band_ = band;
    samples_needed_ = samples < 1 ? 1 : samples;
    reset();
  }
  void reset() { count_ = 0; }

  // True once `samples` consecutive values have stayed within `band` (max - min).
  bool push(float value) {
    const float low = value < low_ ? value : low_;
    const float high = value > high_ ? value : high_;
    if (count_ == 0 || high - low > band_) {
      low_ = high_ = value;  // a new window starts at this sample
      sum_.reset();
      sum_.add(value);
      count_ = 1;
    } else {
      low_ = low;
      high_ = high;
      sum_.add(value);
      ++count_;
    }
    return count_ >= samples_needed_;
  }
  bool stable() const { return count_ >= samples_needed_; }
  // The values in the present window (1: the last push began a new one).
  std::uint32_t count() const { return count_; }
  float mean() const { return sum_.mean(count_); }

 private:
  float band_ = 1.0f;
  std::uint32_t samples_needed_ = 50;
  std::uint32_t count_ = 0;
  float low_ = 0.0f, high_ = 0.0f;
  CompensatedSum sum_;
};

}  // namespace dynweigh::firmware
