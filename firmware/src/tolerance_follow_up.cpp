#include "dynweigh/firmware/tolerance_follow_up.hpp"

namespace dynweigh::firmware {

void ToleranceFollowUp::configure(const Parameters& p) {
  pulse_s_ = p.get(ParameterId::topup_ms) / 1000.0f;
  topup_max_ = std::uint8_t(p.get(ParameterId::topup_max));
}

void ToleranceFollowUp::begin() {
  topups_ = 0;
  stopped_ = false;
  phase_ = Phase::idle;
}

void ToleranceFollowUp::start_top_up() {
  ++topups_;
  phase_ = Phase::topping_up;
}

}  // namespace dynweigh::firmware
