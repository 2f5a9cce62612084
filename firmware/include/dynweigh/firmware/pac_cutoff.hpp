#pragma once
// The pac baseline: predictive adaptive control as in US 6,380,495. The material still arriving
// after the close (the spill) is K1 Q + K2 Q^2, Q the flow the display shows at the close; the valve
// closes when the reading plus that spill reaches the target. After each certified fill the spill
// it measured (the result less the reading at the close) updates K1 and K2 by recursive least
// squares with forgetting. K1's prior is the installation's valve timing and display lag
// (prior_spill_lag_s), K2's zero. A target reached before the flow is measured is timed instead
// (flow_baseline_fill.hpp).
#include "dynweigh/firmware/baseline_learning.hpp"
#include "dynweigh/firmware/close_decision.hpp"
#include "dynweigh/firmware/flow_baseline_fill.hpp"
#include "dynweigh/firmware/parameters.hpp"
#include "dynweigh/firmware/two_parameter_rls.hpp"

namespace dynweigh::firmware {

class PacCutoff {
 public:
  void configure(const Parameters& parameters);
  // The learned values (unlearned parts: the priors). Call before start.
  void restore(const PacLearned& learned);
  PacLearned learned() const { return {spill_.state(), fill_.blind().state()}; }
  void start(float target_g) { fill_.start(target_g); }
  CloseDecision step(float filled_g);
  float prediction_g() const { return fill_.prediction_g(); }
  void learn(float final_g);
  float spill_g(float flow_kg_s) const { return spill_.predict(flow_kg_s, flow_kg_s * flow_kg_s); }

 private:
  void reset_to_prior();
  FlowBaselineFill fill_;
  TwoParameterRls spill_;
  float prior_k1_ = 0.0f;
  float prior_flow_kg_s_ = 0.0f;
};

}  // namespace dynweigh::firmware
