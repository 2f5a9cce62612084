#pragma once
// The flowpreact baseline, as Rice Lake's FLOW preact and the flow-times-delay of open-source
// grind-by-weight firmwares: the preact is the flow the display shows times a lag, and the valve
// closes when the reading plus the preact reaches the target. After each certified fill the lag
// takes a damped share of the error, as seconds of the flow at the close. Its prior is the
// installation's valve timing and display lag (prior_spill_lag_s). A target reached before the
// flow is measured is timed instead (flow_baseline_fill.hpp).
#include "dynweigh/firmware/baseline_learning.hpp"
#include "dynweigh/firmware/close_decision.hpp"
#include "dynweigh/firmware/flow_baseline_fill.hpp"
#include "dynweigh/firmware/parameters.hpp"

namespace dynweigh::firmware {

class FlowPreactCutoff {
 public:
  void configure(const Parameters& parameters);
  void restore(const FlowPreactLearned& learned);
  FlowPreactLearned learned() const { return {lag_s_, fills_, fill_.blind().state()}; }
  void start(float target_g) { fill_.start(target_g); }
  CloseDecision step(float filled_g);
  float prediction_g() const { return fill_.prediction_g(); }
  void learn(float final_g);
  float lag_s() const { return lag_s_; }

 private:
  FlowBaselineFill fill_;
  float prior_lag_s_ = 0.0f;
  float lag_s_ = 0.0f;
  std::uint16_t fills_ = 0;
};

}  // namespace dynweigh::firmware
