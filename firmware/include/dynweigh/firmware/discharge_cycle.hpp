#pragma once
// Emptying the weigh hopper through its discharge gate, with gate proof: the gate is commanded
// open and its feedback must say open within kGateStrokeLimitMs; the hopper is empty once the gross
// weight stays within empty_band_g of the zero (the empty hopper's weight: zero the scale with the
// hopper empty) and stable (stable_band_g for stable_ms); the gate is then commanded closed and
// its feedback must say closed within the same limit. An opened gate that has not emptied the
// hopper by discharge_timeout_s after the command is a fault too.
#include <cstdint>

#include "dynweigh/firmware/io.hpp"
#include "dynweigh/firmware/parameters.hpp"
#include "dynweigh/firmware/stable_weight_detector.hpp"

namespace dynweigh::firmware {

class DischargeCycle {
 public:
  // A gate module's stroke is well under a second; one that has not reached its limit switch by
  // then is stuck (the same limit for opening and closing).
  static constexpr float kGateStrokeLimitMs = 2000.0f;

  enum class Phase : std::uint8_t { idle, opening, emptying, closing };
  enum class Outcome : std::uint8_t { running, emptied, gate_not_open, gate_not_closed, not_empty };

  void configure(const Parameters& p);
  void start();
  // The gate is commanded closed at once, unproven (a fault or `abort`).
  void abort() { phase_ = Phase::idle; }
  bool active() const { return phase_ != Phase::idle; }
  Phase phase() const { return phase_; }
  GateCommand gate() const {
    return phase_ == Phase::opening || phase_ == Phase::emptying ? GateCommand::open : GateCommand::closed;
  }
  // One jiffy: the filtered gross weight and the gate's feedback.
  Outcome step(float gross_g, GatePosition position);

 private:
  Outcome finish(Outcome outcome) {
    phase_ = Phase::idle;
    return outcome;
  }

  Phase phase_ = Phase::idle;
  std::uint32_t jiffies_ = 0;        // since the open command
  std::uint32_t phase_jiffies_ = 0;  // since the phase began
  std::uint32_t stroke_limit_jiffies_ = 200;
  std::uint32_t timeout_jiffies_ = 3000;
  float empty_band_g_ = 20.0f;
  StableWeightDetector stable_;
};

}  // namespace dynweigh::firmware
