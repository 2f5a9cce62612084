#include "dynweigh/firmware/dosing_cycle.hpp"

#include <cmath>

namespace dynweigh::firmware {

void DosingCycle::configure(const Parameters& p) {
  model_.configure(p);
  jiffy_s_ = p.get(ParameterId::jiffy_ms) / 1000.0f;
  preact_g_ = p.get(ParameterId::preact_g);
  timeout_s_ = p.get(ParameterId::dose_timeout_s);
  stable_.configure(p.get(ParameterId::stable_band_g),
                    std::uint32_t(p.get(ParameterId::stable_ms) / p.get(ParameterId::jiffy_ms)));
}

void DosingCycle::start(std::int32_t target_g, DosingStrategy strategy, float start_weight_g) {
  result_ = DoseResult{};
  result_.target_g = target_g;
  result_.strategy = strategy;
  start_weight_g_ = start_weight_g;
  jiffies_ = 0;
  last_prediction_g_ = 0.0f;
  close_delay_fraction_ = 0.0f;
  model_.start(start_weight_g);
  stable_.reset();
  phase_ = Phase::dosing;
  valve_ = ValveCommand::open;
}

bool DosingCycle::should_close(float net_weight_g, float filtered_weight_g) {
  const float target = float(result_.target_g);
  if (result_.strategy == DosingStrategy::preact) {
    last_prediction_g_ = filtered_weight_g - start_weight_g_ + preact_g_;
    return last_prediction_g_ >= target;
  }
  last_prediction_g_ = model_.observe(net_weight_g);
  // Close at the jiffy whose half-way point the prediction crosses: the error is then at most
  // half a jiffy's growth either way, not a whole jiffy's late.
  return last_prediction_g_ + 0.5f * model_.growth_per_jiffy_g() >= target;
}

DosingCycle::Outcome DosingCycle::step(float net_weight_g, float filtered_weight_g) {
  if (phase_ == Phase::idle) return Outcome::running;
  ++jiffies_;
  const float elapsed_s = float(jiffies_) * jiffy_s_;
  if (phase_ == Phase::dosing) {
    if (should_close(net_weight_g, filtered_weight_g)) {
      valve_ = ValveCommand::closed;
      phase_ = Phase::settling;
      result_.cutoff_jiffy = jiffies_;
      const float settle_s = model_.settle_delay_s() + 0.1f;
      settle_from_jiffy_ = jiffies_ + std::uint32_t(std::ceil(settle_s / jiffy_s_));
    } else if (elapsed_s > timeout_s_) {
      abort();
      return Outcome::timed_out;
    }
    return Outcome::running;
  }
  // Settling: only once the last grain has landed does a stable reading mean the fill is complete.
  if (jiffies_ < settle_from_jiffy_) return Outcome::running;
  if (stable_.push(filtered_weight_g)) {
    result_.final_g = std::int32_t(std::lround(stable_.mean() - start_weight_g_));
    result_.time_ms = std::uint32_t(std::lround(elapsed_s * 1000.0f));
    phase_ = Phase::idle;
    return Outcome::certified;
  }
  if (float(jiffies_ - result_.cutoff_jiffy) * jiffy_s_ > settle_limit_s_) {
    abort();
    return Outcome::never_stable;
  }
  return Outcome::running;
}

}  // namespace dynweigh::firmware
