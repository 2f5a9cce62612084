#pragma once
// A baseline's close for a target the fill reaches before its flow can be measured through the
// display (a small target on a plant whose stream takes long to land or to show): the fill is
// then timed. The law, fill = a t + b with t from the open command to the close, is learned by
// least squares from every certified fill of the strategy (the flow a, and b: what the opening and
// the flow's start-up lose, less the valve's let-through at the close). Its prior is the installation
// parameters' Beverloo flow, on the high side so that the first fill closes early rather than late.
#include "dynweigh/firmware/parameters.hpp"
#include "dynweigh/firmware/two_parameter_rls.hpp"

namespace dynweigh::firmware {

class BlindClose {
 public:
  void configure(const Parameters& parameters);
  // A learned law, or (fills == 0 or not sane) the prior.
  void restore(const TwoParameterRls::State& learned);
  const TwoParameterRls::State& state() const { return law_.state(); }
  // Seconds from the open command at which the law expects `target_g` to be delivered (never before
  // the valve's dead time and a quarter of its stroke: its smallest dose).
  float close_time_s(float target_g) const;
  // The fill certified `final_g` after a close `close_s` after the open.
  void learn(float close_s, float final_g);
  float prior_flow_kg_s() const { return prior_flow_kg_s_; }

 private:
  void reset_to_prior();
  TwoParameterRls law_;
  float prior_flow_kg_s_ = 0.0f;
  float earliest_s_ = 0.0f;
};

}  // namespace dynweigh::firmware
