#pragma once
// The model strategy's plan for a dose, from the accuracy asked for (`param class`, OIML R61 X(x))
// and its own uncertainty about where a close now would end. The fastest plan that meets the class:
//   full   full flow to the close, when twice the uncertainty fits in the class's warning limit;
//   fine   full flow, then a half-open fine feed before the close (less in flight, re-measured),
//          when the stream is measured, the half-open close fits, and the full one would miss by
//          enough that its undershoot would likely need a pulse (a pulse waits for its grains to
//          land; the fine feed only slows the last of the fill). It is chosen before its switch
//          point (the half-open stream must land and be measured before the close), never after;
//          `model_fine_s` > 0 runs one of that length on every measured dose instead;
//   topup  a deliberate undershoot: the close aims short by what does not fit, so that the fill
//          ends below the target rather than over it, and top-up pulses finish it.
// The uncertainty: a close before the stream is measured rests on the prior (off by up to 40 %:
// a fifth of the fill, one sigma); a measured one on the flow's fluctuation seen in this dose and
// the estimator's error, both over the material in flight at the close, and, while the stream is
// young, on its growth: a landing rate still climbing above its mean means the flow leaving the
// orifice now is more than the mean that predicts the material in flight.
#include <cstdint>

namespace dynweigh::firmware {

enum class DosePlan : std::uint8_t { full = 0, fine = 1, topup = 2 };
const char* dose_plan_name(DosePlan plan);

// How far short of its target a model fill may end without topping up, given the class's warning
// limit (TL1): after a close meant to hit the target, half of it (the fills' scatter averages out);
// after a deliberate undershoot, 0.3 of it, below the quarter of the in-service limit (0.36 TL1)
// R61 allows the fills' mean, since every such fill ends short.
float model_top_up_shortfall_g(DosePlan plan, float warn_low_g);

// A half-open fine feed as the plan sees it: whether its switch point is still ahead, whether
// `model_fine_s` runs one on every measured dose anyway (the plan is then `fine` wherever half open
// fits, and aims at the target), and the full-open flow (the half-open close lets through half of
// it, by a timing no close confirmed).
struct FineFeedOutlook {
  bool in_reach = false;
  bool every_dose = false;
  float full_flow_g_s = 0.0f;
};

struct PlanChoice {
  DosePlan plan = DosePlan::full;
  float sigma_g = 0.0f;   // the uncertainty of a close now, one standard deviation
  float limit_g = 0.0f;   // the class's warning limit (TL1) at the target
  float margin_g = 0.0f;  // how far short of the target the close aims
};

class DosePlanner {
 public:
  static constexpr float kSigmas = 2.0f;
  static constexpr float kBlindShare = 0.2f;        // one sigma of a blind close on the prior, share of the fill
  // ... timed by an open-time law two fills taught: the law knows the mean fill, not this one's flow
  // (fluctuating 1-6 % rms, not averaged out over a short fill) nor its start-up's scatter. The
  // closes it timed on the plant family scattered by more than 3 % of the fill, and on valves whose
  // jitter is a large part of a short open time by far more (taken as 6 %, they landed 3.2 sigmas
  // from their prediction rms at 500 g, 1.7 at 1 kg, 1.2 at 2 kg). The half-open pulses finish a fill
  // to within a few grams (the valve's feedback times their travel), so aiming 10 % short costs a
  // pulse and saves an overdose (docs/plant-family.md).
  static constexpr float kLearnedBlindShare = 0.10f;
  static constexpr float kEstimatorShare = 0.01f;   // the estimator's error, share of the in-flight
  // Until a measured close of the material has shown what the valve lets through after the close
  // command (learned_fill_law.hpp), a measured close takes it from the valve's timing in use and
  // the gate's shape: a datasheet's or a feedback's timing that no close has confirmed. One sigma of
  // 20 ms of the flow, beside the stream's own uncertainty (the first 2 kg measured close on the
  // slow-valve scene, 200 ms of stroke, came out 68 g, and in another series 107 g, above its
  // prediction: about 30 and 45 ms of its 2.4 kg/s).
  static constexpr float kUnlearnedLetThroughS = 0.02f;
  // The in-flight mass is off by the flow's fluctuation averaged over the flight
  // (model/fluctuation_average.hpp), whose correlation time no dose measures: taken in the upper
  // half of the 0.05-0.3 s the plant family spans, so that the margin errs on the safe side.
  static constexpr float kFluctuationCorrelationS = 0.2f;
  // A stream measured for less than this is young: its flow may still be starting up (the flow's
  // start-up is 0.05 to 0.5 s, the valve's stroke up to 0.3 s, seen after the fall).
  static constexpr float kYoungStreamS = 1.0f;
  static constexpr float kRecentRateS = 0.05f;  // the recent rate's time constant, against the mean
  // A fine feed costs the half-open stream's landing and measuring at half the flow; a top-up costs
  // a pulse and a second landing. The fine feed pays where the undershoot would more likely than not
  // end below the top-up threshold (0.3 TL1): twice the full close's uncertainty beyond 1.3 TL1.
  static constexpr float kFineWorthLimits = 1.3f;
  // The half-open stream measured again before the close, after it has landed.
  static constexpr float kFineMeasureS = 0.3f;

  // `class_x` the OIML class asked for; `half_flow_ratio` what half open lets through of full;
  // `jiffy_s` the control period.
  void configure(float class_x, float half_flow_ratio, float jiffy_s);
  // The class's warning limit (TL1) at `target_g`.
  float class_limit_g(float target_g) const;
  // How far from `target_g` the class allows the mean of a series of fills: a quarter of its
  // in-service limit (OIML R61).
  float class_mean_limit_g(float target_g) const;
  void start();
  // Each jiffy the stream is measured: the landing rate, for its fluctuation.
  void observe_rate(float rate_g_per_jiffy);
  // The plan if the close came now: `predicted_g` the fill a close now would give, `in_flight_g`
  // what is on its way (falling, and let through by the closing valve), `measuring` whether the
  // stream has been measured.
  // `law_taught`: a blind close is timed by the open-time law this material's fills taught.
  // `flight_s`: the time the material in flight took to leave the orifice (0: a fluctuation it
  // does not average at all). `let_through_sigma_g`: what a measured close may be off by because
  // no measured close of this material has yet shown what the valve lets through.
  // `measured_sigma_scale`: what this material's measured closes showed of that uncertainty
  // (measured_close_spread.hpp); it scales a measured close's sigma. `fine`: whether a fine feed
  // may still be chosen (none unless in reach).
  PlanChoice choose(float target_g, float predicted_g, float in_flight_g, bool measuring, bool law_taught = false,
                    float flight_s = 0.0f, float let_through_sigma_g = 0.0f, float measured_sigma_scale = 1.0f,
                    FineFeedOutlook fine = {}) const;
  float fluctuation() const;  // the landing rate's relative standard deviation in this dose
  // While the stream is young, how far its recent landing rate is above its mean, as a share of
  // the mean; 0 once it is not young, or not growing.
  float growth() const;

 private:
  bool fine_feed_pays(float settled_stream_g, float stream_g, float limit_g) const;
  bool half_open_fits(float stream_g, float limit_g) const;
  PlanChoice fine_feed_choice(PlanChoice c, float stream_g, float scale, float full_flow_g_s) const;

  float class_x_ = 1.0f;
  float half_flow_ratio_ = 0.5f;
  std::uint32_t young_rates_ = 100;
  float recent_gain_ = 0.2f;
  std::uint32_t rates_ = 0;
  float mean_ = 0.0f;
  float m2_ = 0.0f;
  float recent_ = 0.0f;
};

}  // namespace dynweigh::firmware
