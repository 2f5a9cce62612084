#pragma once
// What follows a certified result outside its reject band (`param tol_action`): nothing (accept), a
// wait for the operator's `accept` or `topup` (hold), or top-up pulses: the valve opens for
// `topup_ms`, closes, and the scale settles again (stable_band_g for stable_ms, standstill_timeout_s
// at most) before the result is judged anew; at most `topup_max` pulses a dose.
#include <cstdint>

#include "dynweigh/firmware/io.hpp"
#include "dynweigh/firmware/parameters.hpp"
#include "dynweigh/firmware/stable_weight_detector.hpp"

namespace dynweigh::firmware {

class ToleranceFollowUp {
 public:
  enum class Phase : std::uint8_t { idle, holding, pulsing, settling };
  enum class Event : std::uint8_t { none, settled, never_stable };

  void configure(const Parameters& parameters);
  // A certified result from a dose that started at `start_weight_g`: no top-up yet.
  void begin(float start_weight_g);
  void hold() { phase_ = Phase::holding; }
  bool may_top_up() const { return topups_ < topup_max_; }
  void start_top_up();
  // A fault, an abort, or the result reported: the valve stays closed.
  void finish() { phase_ = Phase::idle; }

  // One jiffy with the filtered gross weight.
  Event step(float filtered_weight_g);
  ValveCommand valve() const { return phase_ == Phase::pulsing ? ValveCommand::open : ValveCommand::closed; }
  // After `settled`: the fill from the dose's start to the settled weight.
  float settled_fill_g() const { return stable_.mean() - start_weight_g_; }

  Phase phase() const { return phase_; }
  bool active() const { return phase_ != Phase::idle; }
  std::uint8_t topups() const { return topups_; }

 private:
  Phase phase_ = Phase::idle;
  StableWeightDetector stable_;
  float start_weight_g_ = 0.0f;
  std::uint32_t jiffies_ = 0;
  std::uint32_t pulse_jiffies_ = 1;
  std::uint32_t settle_limit_jiffies_ = 1000;
  std::uint8_t topups_ = 0;
  std::uint8_t topup_max_ = 0;
};

}  // namespace dynweigh::firmware
