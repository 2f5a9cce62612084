#include "dynweigh/firmware/discharge_cycle.hpp"

#include <cmath>

namespace dynweigh::firmware {

void DischargeCycle::configure(const Parameters& p) {
  const float jiffy_ms = p.get(ParameterId::jiffy_ms);
  stroke_limit_jiffies_ = std::uint32_t(kGateStrokeLimitMs / jiffy_ms);
  timeout_jiffies_ = std::uint32_t(p.get(ParameterId::discharge_timeout_s) * 1000.0f / jiffy_ms);
  empty_band_g_ = p.get(ParameterId::empty_band_g);
  stable_.configure(p.get(ParameterId::stable_band_g), std::uint32_t(p.get(ParameterId::stable_ms) / jiffy_ms));
}

void DischargeCycle::start() {
  phase_ = Phase::opening;
  jiffies_ = 0;
  phase_jiffies_ = 0;
  stable_.reset();
}

DischargeCycle::Outcome DischargeCycle::step(float gross_g, GatePosition position) {
  if (phase_ == Phase::idle) return Outcome::running;
  ++jiffies_;
  ++phase_jiffies_;
  switch (phase_) {
    case Phase::opening:
      if (position == GatePosition::open) {
        phase_ = Phase::emptying;
        phase_jiffies_ = 0;
      } else if (phase_jiffies_ > stroke_limit_jiffies_) {
        return finish(Outcome::gate_not_open);
      }
      return Outcome::running;
    case Phase::emptying: {
      const bool stable = stable_.push(gross_g);
      if (stable && std::fabs(stable_.mean()) <= empty_band_g_) {
        phase_ = Phase::closing;
        phase_jiffies_ = 0;
      } else if (jiffies_ > timeout_jiffies_) {
        return finish(Outcome::not_empty);
      }
      return Outcome::running;
    }
    case Phase::closing:
      if (position == GatePosition::closed) return finish(Outcome::emptied);
      if (phase_jiffies_ > stroke_limit_jiffies_) return finish(Outcome::gate_not_closed);
      return Outcome::running;
    case Phase::idle:
      break;
  }
  return Outcome::running;
}

}  // namespace dynweigh::firmware
