#include "dynweigh/firmware/display_filter.hpp"

#include <cmath>

namespace dynweigh::firmware {

void DisplayFilter::configure(FilterKind kind, float corner_hz, float jiffy_s) {
  kind_ = kind;
  // Two first-order stages: critically damped, no overshoot on a step.
  smoothing_ = 1.0f - std::exp(-2.0f * float(M_PI) * corner_hz * jiffy_s);
  // A moving average of length L has its first zero at 1/(L dt): put it at twice the corner.
  const float length = std::round(1.0f / (2.0f * corner_hz * jiffy_s));
  window_length_ = length < 1.0f ? 1 : (length > float(kMaxAverage) ? kMaxAverage : std::size_t(length));
  primed_ = false;
}

void DisplayFilter::reset(float value) {
  stage1_ = output_ = value;
  for (std::size_t i = 0; i < window_length_; ++i) window_[i] = value;
  window_sum_.reset();
  for (std::size_t i = 0; i < window_length_; ++i) window_sum_.add(value);
  head_ = 0;
  count_ = window_length_;
  primed_ = true;
}

float DisplayFilter::push(float value) {
  if (!primed_) reset(value);
  switch (kind_) {
    case FilterKind::none:
      output_ = value;
      break;
    case FilterKind::average:
      window_sum_.add(value);
      window_sum_.add(-window_[head_]);
      window_[head_] = value;
      head_ = (head_ + 1) % window_length_;
      if (head_ == 0) {  // re-add once a window so rounding cannot accumulate over a day
        window_sum_.reset();
        for (std::size_t i = 0; i < window_length_; ++i) window_sum_.add(window_[i]);
      }
      output_ = window_sum_.mean(std::uint32_t(count_));
      break;
    case FilterKind::iir:
      stage1_ += smoothing_ * (value - stage1_);
      output_ += smoothing_ * (stage1_ - output_);
      break;
  }
  return output_;
}

}  // namespace dynweigh::firmware
