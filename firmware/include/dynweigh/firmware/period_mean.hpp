#pragma once
// The mean of the last N samples, N up to a capacity fixed at compile time. Taken over one period of
// the platform's ringing it cancels the ringing, which a low-pass filter only attenuates: a heavily
// loaded platform rings slowly and long, and its swing through the display filter can exceed a fault
// threshold by itself.
#include <cstdint>

namespace dynweigh::firmware {

class PeriodMean {
 public:
  static constexpr std::uint32_t kCapacity = 128;

  void reset(std::uint32_t samples) {
    window_ = samples < 1 ? 1 : (samples > kCapacity ? kCapacity : samples);
    count_ = 0;
    head_ = 0;
    sum_ = 0.0f;
  }
  void push(float value) {
    if (count_ == window_) sum_ -= samples_[head_];
    else ++count_;
    samples_[head_] = value;
    sum_ += value;
    head_ = (head_ + 1) % window_;
  }
  // The mean so far (of fewer samples until the window has filled); 0 before any.
  float mean() const { return count_ ? sum_ / float(count_) : 0.0f; }

 private:
  float samples_[kCapacity] = {};
  std::uint32_t window_ = 1;
  std::uint32_t count_ = 0;
  std::uint32_t head_ = 0;
  float sum_ = 0.0f;
};

}  // namespace dynweigh::firmware
