#pragma once
// The `model` strategy's view of a fill: it fits a line to the unfiltered weight since the stream
// settled (slope = landing rate, end = present reading, no filter lag) and predicts the final weight
// with the ideal model of PHYSICS §1 (corrected sign), the pile's rise and the valve's let-through.
// Before the first impact it has no measurement and predicts from the configured geometry instead.
#include <cstdint>

#include "dynweigh/firmware/parameters.hpp"
#include "dynweigh/model/final_weight_prediction.hpp"
#include "dynweigh/model/sliding_line_fit.hpp"

namespace dynweigh::firmware {

class ModelCutoff {
 public:
  static constexpr std::uint32_t kMinimumFitSamples = 10;

  void configure(const Parameters& parameters);
  // Called at the jiffy the valve is commanded open; weights are net grams on the scale.
  void start(float start_weight_g);
  // One unfiltered sample per jiffy; returns the predicted final fill (grams added by this dose)
  // if the valve were commanded closed now.
  float observe(float net_weight_g);
  // Grams the fill grows per jiffy at the present flow, for timing the close within the jiffy.
  float growth_per_jiffy_g() const { return growth_per_jiffy_g_; }
  // Seconds from the close command until the last grain has landed.
  float settle_delay_s() const;
  bool measuring() const { return fit_.count() >= kMinimumFitSamples; }
  float measured_flow_kg_s() const { return growth_per_jiffy_g_ / (1000.0f * jiffy_s_); }
  // Orifice to pile top once `net_weight_g` is on the scale (the learning table's key).
  float fall_height_m(float net_weight_g) const;

  // The valve goes to half: the flow, the open area and the let-through change, so the fit starts
  // again once the half-open stream has reached the pile. Until then the prediction at the switch
  // grows at the half-open flow Beverloo gives.
  void switch_to_half(float predicted_now_g);
  bool fine_feeding() const { return fine_; }

 private:
  float prior_prediction_g() const;

  model::CutoffGeometry<float> geometry_;
  float full_area_m2_ = 0.0f;
  float full_closing_flow_s_ = 0.0f;
  float half_closing_flow_s_ = 0.0f;  // in seconds of half-open flow
  float half_flow_ratio_ = 0.5f;      // Beverloo: half-open flow / full flow
  float half_transition_s_ = 0.0f;    // dead time and half a stroke
  float jiffy_s_ = 0.01f;
  float prior_rate_kg_s_ = 0.0f;
  float opening_delay_s_ = 0.0f;
  std::uint32_t settle_jiffies_ = 30;
  float impact_threshold_g_ = 20.0f;
  model::SlidingLineFit<float, 128> fit_;

  float start_weight_g_ = 0.0f;
  std::uint32_t jiffies_ = 0;
  std::uint32_t impact_jiffy_ = 0;
  bool impacted_ = false;
  float growth_per_jiffy_g_ = 0.0f;
  float last_fall_time_s_ = 0.0f;
  bool fine_ = false;
  float predicted_at_switch_g_ = 0.0f;
  float measured_full_rate_g_per_jiffy_ = 0.0f;
  std::uint32_t switch_jiffy_ = 0;
};

}  // namespace dynweigh::firmware
