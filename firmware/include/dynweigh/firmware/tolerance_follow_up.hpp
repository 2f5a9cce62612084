#pragma once
// What follows a certified result outside its band: nothing (accept), a wait for the operator's
// `accept` or `topup` (hold), or top-up pulses, at most `topup_max` a dose. The pulses themselves
// are the dose's (DosingCycle::start_top_up): sized from the flow it measured and certified as it
// certified its close; this counts them and keeps the held state.
#include <cstdint>

#include "dynweigh/firmware/parameters.hpp"

namespace dynweigh::firmware {

class ToleranceFollowUp {
 public:
  enum class Phase : std::uint8_t { idle, holding, topping_up };

  void configure(const Parameters& parameters);
  // A certified result: no top-up yet.
  void begin();
  void hold() { phase_ = Phase::holding; }
  bool may_top_up() const { return topups_ < topup_max_ && !stopped_; }
  // How many more pulses this dose may give.
  std::uint8_t pulses_left() const { return may_top_up() ? std::uint8_t(topup_max_ - topups_) : 0; }
  void start_top_up();
  // A pulse the scale saw nothing of: no more pulses this dose.
  void stop_topping_up() { stopped_ = true; }
  // A fault, an abort, or the result reported.
  void finish() { phase_ = Phase::idle; }
  // The longest pulse (`topup_ms`), and the only one of a strategy that measured no flow.
  float pulse_s() const { return pulse_s_; }

  Phase phase() const { return phase_; }
  bool active() const { return phase_ != Phase::idle; }
  bool topping_up() const { return phase_ == Phase::topping_up; }
  std::uint8_t topups() const { return topups_; }

 private:
  Phase phase_ = Phase::idle;
  float pulse_s_ = 0.05f;
  std::uint8_t topups_ = 0;
  std::uint8_t topup_max_ = 0;
  bool stopped_ = false;
};

}  // namespace dynweigh::firmware
