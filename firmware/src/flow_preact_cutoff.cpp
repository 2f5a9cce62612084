#include "dynweigh/firmware/flow_preact_cutoff.hpp"

#include <cmath>

namespace dynweigh::firmware {
namespace {
// Rice Lake's learn: most of the last error, each step capped so one odd fill cannot throw the lag
// far; a measured flow below this is no flow to divide an error by.
constexpr float kLearnGain = 0.6f;
constexpr float kCapShare = 0.5f;
constexpr float kCapBaseS = 0.05f;
constexpr float kMinimumFlowKgS = 0.001f;
// A lag beyond this is no preact (a stored value out of reason).
constexpr float kLagLimitS = 10.0f;
}  // namespace

void FlowPreactCutoff::configure(const Parameters& p) {
  fill_.configure(p);
  prior_lag_s_ = prior_spill_lag_s(p);
  lag_s_ = prior_lag_s_;
  fills_ = 0;
}

void FlowPreactCutoff::restore(const FlowPreactLearned& learned) {
  const bool usable = learned.fills > 0 && std::isfinite(learned.lag_s) && std::fabs(learned.lag_s) <= kLagLimitS;
  lag_s_ = usable ? learned.lag_s : prior_lag_s_;
  fills_ = usable ? learned.fills : 0;
  fill_.blind().restore(learned.blind);
}

CloseDecision FlowPreactCutoff::step(float filled_g) {
  return fill_.step(filled_g, [this](float flow_kg_s) { return 1000.0f * flow_kg_s * lag_s_; });
}

void FlowPreactCutoff::learn(float final_g) {
  const FlowBaselineFill::AtClose& c = fill_.at_close();
  if (c.measured && c.flow_kg_s > kMinimumFlowKgS) {
    const float error_s = (final_g - fill_.target_g()) / (1000.0f * c.flow_kg_s);
    const float cap = kCapShare * std::fabs(lag_s_) + kCapBaseS;
    float step = kLearnGain * error_s;
    step = step > cap ? cap : (step < -cap ? -cap : step);
    const float lag = lag_s_ + step;
    lag_s_ = lag > kLagLimitS ? kLagLimitS : (lag < -kLagLimitS ? -kLagLimitS : lag);
    if (fills_ < 0xFFFF) ++fills_;
  }
  fill_.learn_blind(final_g);
}

}  // namespace dynweigh::firmware
