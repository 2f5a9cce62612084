#pragma once
// The display filter (`param filter`): what `status`, the test data and the baselines see.
// The model strategy does not look through it; it fits the unfiltered samples instead.
#include <cstddef>

#include "dynweigh/firmware/compensated_sum.hpp"
#include "dynweigh/firmware/parameters.hpp"

namespace dynweigh::firmware {

class DisplayFilter {
 public:
  static constexpr std::size_t kMaxAverage = 200;

  void configure(FilterKind kind, float corner_hz, float jiffy_s);
  void reset(float value);
  // The next sample primes the filter afresh: after a fault, a pegged history is no evidence.
  void restart() { primed_ = false; }
  float push(float value);
  float value() const { return output_; }

 private:
  FilterKind kind_ = FilterKind::iir;
  float smoothing_ = 1.0f;  // per-stage weight of the new sample (iir)
  float stage1_ = 0.0f, output_ = 0.0f;
  float window_[kMaxAverage] = {};
  std::size_t window_length_ = 1, head_ = 0, count_ = 0;
  CompensatedSum window_sum_;  // a plain float running sum drifts over a day of samples
  bool primed_ = false;
};

}  // namespace dynweigh::firmware
