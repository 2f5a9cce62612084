#pragma once
// What the pac and flowpreact baselines share: one fill seen through the display. Until the flow is
// measured (display_flow_meter.hpp) the close is timed by the learned blind law (blind_close.hpp),
// which closes early only for a target the fill reaches before its flow can be weighed. Once the flow
// is measured, the strategy's own spill prediction decides: close when the reading plus the spill
// at this flow reaches the target, timed within the jiffy. It keeps what the close saw, for learning.
#include <cstdint>

#include "dynweigh/firmware/blind_close.hpp"
#include "dynweigh/firmware/close_decision.hpp"
#include "dynweigh/firmware/display_flow_meter.hpp"
#include "dynweigh/firmware/parameters.hpp"

namespace dynweigh::firmware {

// The spill's lag a prior can know, in seconds of flow: the valve's dead time and half its stroke
// (what passes while it closes) and the display filter's lag behind a steady rise. The stream in
// flight and its impact on the scale about cancel. 20 % on top, so a first fill closes early.
float prior_spill_lag_s(const Parameters& parameters);

class FlowBaselineFill {
 public:
  // What the reading saw at the close command.
  struct AtClose {
    bool measured = false;    // closed on the spill prediction (else timed blind)
    float time_s = 0.0f;      // from the open command
    float flow_kg_s = 0.0f;   // the measured flow (measured closes)
    float reading_g = 0.0f;   // the filtered weight added by the fill
  };

  void configure(const Parameters& parameters);
  BlindClose& blind() { return blind_; }
  const BlindClose& blind() const { return blind_; }
  void start(float target_g);

  // One fresh jiffy with the filtered weight added since the open; `spill_g(flow_kg_s)` the
  // strategy's prediction of what still arrives after a close at that flow.
  template <typename Spill>
  CloseDecision step(float filled_g, const Spill& spill_g) {
    meter_.push(filled_g);
    const float now_s = float(jiffies_++) * jiffy_s_;
    CloseDecision d;
    if (!meter_.measured()) {
      const float close_s = blind_.close_time_s(target_g_);
      prediction_g_ = target_g_ + (now_s - close_s) * blind_.state().theta1;
      if (close_s >= now_s + jiffy_s_) return d;
      d.close = true;
      const float fraction = (close_s - now_s) / jiffy_s_;
      d.fraction = fraction < 0.0f ? 0.0f : (fraction > 0.99f ? 0.99f : fraction);
      at_close_ = AtClose{false, now_s + d.fraction * jiffy_s_, 0.0f, filled_g};
      return d;
    }
    const float flow = meter_.flow_kg_s();
    const float growth_g = 1000.0f * flow * jiffy_s_;
    prediction_g_ = filled_g + spill_g(flow);
    d = close_within_jiffy(prediction_g_, growth_g, target_g_);
    if (d.close) at_close_ = AtClose{true, now_s + d.fraction * jiffy_s_, flow, filled_g + d.fraction * growth_g};
    return d;
  }

  float prediction_g() const { return prediction_g_; }
  float target_g() const { return target_g_; }
  const AtClose& at_close() const { return at_close_; }
  // Every certified fill teaches the blind law (a long fill tells the flow too).
  void learn_blind(float final_g) { blind_.learn(at_close_.time_s, final_g); }

 private:
  DisplayFlowMeter meter_;
  BlindClose blind_;
  float jiffy_s_ = 0.01f;
  float target_g_ = 0.0f;
  float prediction_g_ = 0.0f;
  std::uint32_t jiffies_ = 0;
  AtClose at_close_;
};

}  // namespace dynweigh::firmware
