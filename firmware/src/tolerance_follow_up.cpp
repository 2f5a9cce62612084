#include "dynweigh/firmware/tolerance_follow_up.hpp"

#include <cmath>

namespace dynweigh::firmware {

void ToleranceFollowUp::configure(const Parameters& p) {
  const float jiffy_ms = p.get(ParameterId::jiffy_ms);
  pulse_jiffies_ = std::uint32_t(std::ceil(p.get(ParameterId::topup_ms) / jiffy_ms));
  if (pulse_jiffies_ < 1) pulse_jiffies_ = 1;
  settle_limit_jiffies_ = std::uint32_t(p.get(ParameterId::standstill_timeout_s) * 1000.0f / jiffy_ms);
  stable_.configure(p.get(ParameterId::stable_band_g), std::uint32_t(p.get(ParameterId::stable_ms) / jiffy_ms));
  topup_max_ = std::uint8_t(p.get(ParameterId::topup_max));
}

void ToleranceFollowUp::begin(float start_weight_g) {
  start_weight_g_ = start_weight_g;
  topups_ = 0;
  phase_ = Phase::idle;
}

void ToleranceFollowUp::start_top_up() {
  ++topups_;
  jiffies_ = 0;
  phase_ = Phase::pulsing;
}

ToleranceFollowUp::Event ToleranceFollowUp::step(float filtered_weight_g) {
  if (phase_ == Phase::pulsing) {
    if (++jiffies_ >= pulse_jiffies_) {
      phase_ = Phase::settling;
      jiffies_ = 0;
      stable_.reset();
    }
    return Event::none;
  }
  if (phase_ != Phase::settling) return Event::none;
  if (stable_.push(filtered_weight_g)) {
    phase_ = Phase::idle;
    return Event::settled;
  }
  if (++jiffies_ >= settle_limit_jiffies_) {
    phase_ = Phase::idle;
    return Event::never_stable;
  }
  return Event::none;
}

}  // namespace dynweigh::firmware
