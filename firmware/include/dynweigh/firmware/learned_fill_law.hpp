#pragma once
// The model strategy's memory of a material (material_learning.hpp), and what a certified fill
// teaches it. The open-time law starts from the Beverloo flow of the installation parameters and
// the valve's datasheet timing, and is learned by least squares (two_parameter_rls.hpp); the
// measured close's let-through follows the measured closes' residuals with a bounded gain. Both are bounded: one bad fill cannot run
// them away.
#include "dynweigh/firmware/material_learning.hpp"
#include "dynweigh/firmware/two_parameter_rls.hpp"

namespace dynweigh::firmware {

// How a dose closed, as the next fill needs to know it.
struct CloseRecord {
  bool valid = false;
  bool from_full_open = true;     // no half-open fine feed before the close
  bool measured = false;          // the stream was measured when the close was decided
  float open_s = 0.0f;            // from the open command to the close command
  float prediction_g = 0.0f;      // the model's prediction at the close, with the let-through learned so far
  float flow_g_s = 0.0f;          // the flow at the close
  float let_through_s = 0.0f;     // what the prediction took the valve to let through, in seconds of that flow
};

class LearnedFillLaw {
 public:
  // The prior: Beverloo's full flow for the configured density and bore, and what the datasheet's
  // valve timing loses at the opening less what it lets through at the close, in seconds of flow.
  void configure(float prior_flow_g_s, float prior_lag_s);
  // Forgets, then takes what an earlier fill of this material learned (dropped if not sane).
  void restore(const MaterialLearning& learned);
  const MaterialLearning& learned() const { return learned_; }

  bool knows_open_time_law() const { return learned_.open_time_law.fills > 0; }
  float final_at_open_g(float open_s) const { return law_.predict(open_s, 1.0f); }
  // The open time at which the law delivers `final_g` (0 if its flow is none).
  float open_s_for(float final_g) const;
  float law_flow_g_s() const { return law_.state().theta1; }
  float longest_open_s() const { return learned_.law_longest_open_s; }
  // Seconds of the flow at the close to add to a measured close's prediction that takes the valve to
  // let `let_through_in_use_s` through.
  float close_residual_s(float let_through_in_use_s) const;

  // A certified fill of `final_g` that closed as `close` says; `close_sigma_g` the uncertainty the
  // plan gave a measured close before its scale (0: none given).
  void learn(const CloseRecord& close, float final_g, float close_sigma_g = 0.0f);
  // What the plan multiplies a measured close's uncertainty by (measured_close_spread.hpp).
  float measured_sigma_scale() const { return learned_.measured_closes.sigma_scale(); }

 private:
  void learn_open_time(float open_s, float final_g);
  void extend_reach_if_short(float open_s, float final_g);
  void learn_let_through(float shown_s);
  TwoParameterRls law_;
  float prior_flow_g_s_ = 0.0f;
  float prior_lag_s_ = 0.0f;
  MaterialLearning learned_{};
};

}  // namespace dynweigh::firmware
