#pragma once
// The reading `zero` and `cal` take: the mean of the raw counts over a window, once that mean has
// stopped moving. Before a calibration exists nothing is known in grams, so steadiness is judged in
// counts: against the load cell's own noise (its second differences' scatter), and for `cal` also
// against a fraction of the span the caller passes as a floor.
//
// The counts first pass three moving averages of kStageJiffies each, which put nulls and deep
// notches over a platform's ringing (5..30 Hz and above); their output is averaged over the window.
// That mean is steady when it has stayed within the tolerance for kSteadyJiffies. Integer sums
// throughout, relative to the first sample: exact for any offset in the int32 range, and a
// decaying ring, a drift or a sway shows as the mean still moving.
#include <cstddef>
#include <cstdint>

namespace dynweigh::firmware {

class StandstillAverage {
 public:
  static constexpr std::uint32_t kStageJiffies = 20;   // 0.2 s: a null at 5, 10, 15 ... Hz
  static constexpr std::uint32_t kBlockJiffies = 10;
  static constexpr std::uint32_t kWindowBlocks = 30;   // the mean over 3 s
  static constexpr std::uint32_t kSteadyBlocks = 10;   // steady for 1 s
  static constexpr std::uint32_t kWindowJiffies = kWindowBlocks * kBlockJiffies;
  static constexpr std::uint32_t kSteadyJiffies = kSteadyBlocks * kBlockJiffies;
  // The fewest samples before the first answer: the stages, the window and the steady time.
  static constexpr std::uint32_t kMinimumJiffies = 3 * kStageJiffies + kWindowJiffies + kSteadyJiffies;
  static constexpr float kNoiseSigmas = 4.0f;  // a still load cell's mean rarely moves more

  // The counts of the empty scale or of the load, as whole counts and a part of one.
  struct Reading {
    std::int32_t whole = 0;
    float fraction = 0.0f;  // in [0, 1)
  };

  void start();
  void push(std::int32_t raw_counts);
  // The mean has been steady within max(floor_counts, what the noise explains) for kSteadyJiffies.
  bool steady(float floor_counts) const;
  // The present mean (valid once steady() can be true).
  Reading mean() const;
  // The present mean minus `origin`, in counts (for a span: exact enough for any two int32 counts).
  float mean_above(std::int32_t origin) const;

 private:
  float noise_tolerance_counts() const;
  static constexpr std::int64_t kMeanDivisor =
      std::int64_t(kWindowJiffies) * kStageJiffies * kStageJiffies * kStageJiffies;

  std::int32_t base_ = 0;
  std::uint32_t samples_ = 0;
  std::int64_t last_x_ = 0;
  float last_step_ = 0.0f;
  // Three cascaded moving sums.
  std::int64_t stage_[3][kStageJiffies] = {};
  std::int64_t stage_sum_[3] = {};
  std::uint32_t stage_head_ = 0;
  // The third stage's output summed per block, and the noise (squared second differences) per block.
  std::int64_t block_sum_ = 0;
  float block_noise_ = 0.0f;
  std::uint32_t block_fill_ = 0;
  std::int64_t window_[kWindowBlocks] = {};
  float window_noise_[kWindowBlocks] = {};
  std::uint32_t window_head_ = 0;
  std::uint32_t blocks_ = 0;
  // The window's sum (the mean times kMeanDivisor) at the last kSteadyBlocks + 1 block ends.
  std::int64_t means_[kSteadyBlocks + 1] = {};
  std::uint32_t means_head_ = 0;
};

}  // namespace dynweigh::firmware
