#include "dynweigh/firmware/standstill_average.hpp"

#include <cmath>

namespace dynweigh::firmware {

// Field by field: a whole-object temporary would put a kilobyte on the caller's stack.
void StandstillAverage::start() {
  samples_ = 0;
  last_x_ = 0;
  last_step_ = 0.0f;
  for (std::uint32_t s = 0; s < 3; ++s) {
    for (std::int64_t& v : stage_[s]) v = 0;
    stage_sum_[s] = 0;
  }
  stage_head_ = 0;
  block_sum_ = 0;
  block_noise_ = 0.0f;
  block_fill_ = 0;
  for (std::int64_t& b : window_) b = 0;
  for (float& n : window_noise_) n = 0.0f;
  window_head_ = 0;
  blocks_ = 0;
  for (std::int64_t& m : means_) m = 0;
  means_head_ = 0;
}

void StandstillAverage::push(std::int32_t raw_counts) {
  if (samples_ == 0) base_ = raw_counts;
  const std::int64_t x = std::int64_t(raw_counts) - base_;
  const float step = float(x - last_x_);
  const float bend = step - last_step_;
  const bool has_bend = samples_ > 1;
  last_x_ = x;
  last_step_ = step;
  ++samples_;

  std::int64_t value = x;
  for (std::uint32_t s = 0; s < 3; ++s) {
    stage_sum_[s] += value - stage_[s][stage_head_];
    stage_[s][stage_head_] = value;
    value = stage_sum_[s];
  }
  stage_head_ = (stage_head_ + 1) % kStageJiffies;
  if (samples_ < 3 * kStageJiffies) return;  // the stages still fill

  block_sum_ += value;
  if (has_bend) block_noise_ += bend * bend;
  if (++block_fill_ < kBlockJiffies) return;
  window_[window_head_] = block_sum_;
  window_noise_[window_head_] = block_noise_;
  window_head_ = (window_head_ + 1) % kWindowBlocks;
  block_sum_ = 0;
  block_noise_ = 0.0f;
  block_fill_ = 0;
  if (++blocks_ < kWindowBlocks) return;
  std::int64_t sum = 0;
  for (const std::int64_t b : window_) sum += b;
  means_[means_head_] = sum;
  means_head_ = (means_head_ + 1) % (kSteadyBlocks + 1);
}

float StandstillAverage::noise_tolerance_counts() const {
  float squares = 0.0f;
  for (const float n : window_noise_) squares += n;
  // White noise of sigma: second differences of variance 6 sigma^2; the window mean then moves by
  // sigma sqrt(2 C) / W over C samples (C the steady time, W the window). Second differences, not
  // first: a platform still ringing below the stages' first null (a lightly damped platform under
  // a test weight, 2 to 3 Hz) would count as noise ten times over in first differences, and the
  // tolerance it widened let a `cal` take a mean the ring still moved (16 g on 20 kg).
  const float sigma = std::sqrt(squares / (6.0f * float(kWindowJiffies)));
  return kNoiseSigmas * sigma * std::sqrt(2.0f * float(kSteadyJiffies)) / float(kWindowJiffies);
}

bool StandstillAverage::steady(float floor_counts) const {
  if (blocks_ < kWindowBlocks + kSteadyBlocks) return false;
  std::int64_t low = means_[0], high = means_[0];
  for (const std::int64_t m : means_) {
    low = m < low ? m : low;
    high = m > high ? m : high;
  }
  const float moved = float(high - low) / float(kMeanDivisor);
  // A reading that never changes by a single count (a quiet cell on a coarse ADC) is steady too.
  const float quantum = 1.0f / float(kWindowJiffies);
  float tolerance = noise_tolerance_counts();
  tolerance = tolerance > floor_counts ? tolerance : floor_counts;
  tolerance = tolerance > quantum ? tolerance : quantum;
  return moved <= tolerance;
}

StandstillAverage::Reading StandstillAverage::mean() const {
  const std::int64_t sum = means_[(means_head_ + kSteadyBlocks) % (kSteadyBlocks + 1)];
  std::int64_t whole = sum / kMeanDivisor;
  std::int64_t rest = sum % kMeanDivisor;
  if (rest < 0) {  // floor, not truncation: the fraction stays in [0, 1)
    --whole;
    rest += kMeanDivisor;
  }
  Reading r;
  r.whole = std::int32_t(base_ + whole);  // a mean of int32 samples is within their range
  r.fraction = float(rest) / float(kMeanDivisor);
  return r;
}

float StandstillAverage::mean_above(std::int32_t origin) const {
  const Reading r = mean();
  return float(std::int64_t(r.whole) - origin) + r.fraction;
}

}  // namespace dynweigh::firmware
