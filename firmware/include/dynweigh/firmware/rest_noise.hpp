#pragma once
// The scale's noise: the rms of the unfiltered net reading about the display filter's while the
// filtered weight stands still, the quietest such rest seen since power-up (DosingCycle forgets it
// when the span changes). A settling fit whose residuals are well above it does not describe the
// reading yet (an impact still relaxing, an avalanche): dosing_cycle.cpp does not certify on it
// (docs/strategies.md, Dynamic weighing).
// The quietest, not the last: between back-to-back fills the filtered weight is still within its
// band while the platform rings, and that rest's rms is the ringing's.
#include <cmath>
#include <cstdint>

namespace dynweigh::firmware {

class RestNoise {
 public:
  // A rest counts once it is this long (0.5 s at 100 samples a second): its rms is then within
  // about 10 % of the noise's.
  static constexpr std::uint32_t kLeastSamples = 50;
  // The mean square runs over the last kSamples or so: an indicator standing idle for days keeps
  // its float's resolution.
  static constexpr std::uint32_t kSamples = 256;

  // The filtered weight moved: the rest before (if long enough) is kept, a new one begins.
  void restart() {
    if (samples_ >= kLeastSamples) keep(mean_square_);
    mean_square_ = 0.0f;
    samples_ = 0;
  }
  // A dose opens from this rest: it counts however long it was (the standstill it passed is long
  // enough for the dose's start weight).
  void keep_this_rest() {
    if (samples_ > 0) keep(mean_square_);
  }
  void push(float deviation_g) {
    if (samples_ < kSamples) ++samples_;
    mean_square_ += (deviation_g * deviation_g - mean_square_) / float(samples_);
  }
  // The quietest rest kept (0 before any).
  float rms_g() const { return std::sqrt(quietest_); }

 private:
  void keep(float mean_square) {
    if (!seen_ || mean_square < quietest_) quietest_ = mean_square;
    seen_ = true;
  }
  float mean_square_ = 0.0f;
  std::uint32_t samples_ = 0;
  float quietest_ = 0.0f;  // the smallest mean square of a rest of kLeastSamples or more
  bool seen_ = false;
};

}  // namespace dynweigh::firmware
