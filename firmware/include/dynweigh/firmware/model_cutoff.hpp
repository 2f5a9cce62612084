#pragma once
// The `model` strategy's view of a fill: from the first impact a Kalman observer separates the
// static mass and the landing rate from the platform's ringing (no filter lag; `model_estimator
// line` fits a line to the unfiltered weight instead, once the ringing has calmed), and the final
// weight follows from the ideal model of docs/physics.md (corrected sign), the pile's rise and the
// valve's let-through. Before the first impact it has no measurement and predicts from the
// configured geometry and the valve's timing instead.
#include <cstdint>

#include "dynweigh/firmware/parameters.hpp"
#include "dynweigh/model/beverloo.hpp"
#include "dynweigh/model/final_weight_prediction.hpp"
#include "dynweigh/model/impact_signature.hpp"
#include "dynweigh/model/opening_estimator.hpp"
#include "dynweigh/model/ringing_flow_observer.hpp"
#include "dynweigh/model/sliding_line_fit.hpp"

namespace dynweigh::firmware {

// What a dose told about the valve and the material (the console's `estimates`): the first impact
// and the valve's dead time it implies, the flow, and the impact's signature early in the stream.
template <typename Scalar>
struct DoseEstimates {
  bool impact_timed = false;
  Scalar first_impact_s = 0;  // from the open command
  Scalar dead_time_s = 0;     // the first impact less the fall from rest (opening_estimator.hpp)
  bool measured = false;
  Scalar flow_kg_s = 0;       // the mean landing rate at the last prediction
  model::ImpactSignature<Scalar> signature{};
};

// Scalar is float on the target; the double instantiation is the reference the numerical stress
// tests run beside it.
template <typename Scalar>
class BasicModelCutoff {
 public:
  static constexpr std::uint32_t kMinimumFitSamples = 10;

  void configure(const Parameters& parameters);
  // Called at the jiffy the valve is commanded open; weights are net grams on the scale.
  void start(Scalar start_weight_g);
  // One unfiltered sample per jiffy; returns the predicted final fill (grams added by this dose)
  // if the valve were commanded closed now.
  Scalar observe(Scalar net_weight_g);
  // Grams the fill grows per jiffy at the present flow, for timing the close within the jiffy.
  Scalar growth_per_jiffy_g() const { return growth_per_jiffy_g_; }
  // Seconds from the close command until the last grain has landed.
  Scalar settle_delay_s() const;
  bool measuring() const {
    return use_observer_ ? observer_.started() && jiffies_ > measure_jiffy_ : fit_.count() >= kMinimumFitSamples;
  }
  Scalar measured_flow_kg_s() const { return growth_per_jiffy_g_ / (Scalar(1000) * jiffy_s_); }
  // Orifice to pile top once `net_weight_g` is on the scale (the learning table's key).
  Scalar fall_height_m(Scalar net_weight_g) const;

  // The valve goes to half: the flow, the open area and the let-through change, so the fit starts
  // again once the half-open stream has reached the pile. Until then the prediction at the switch
  // grows at the half-open flow Beverloo gives.
  void switch_to_half(Scalar predicted_now_g);
  bool fine_feeding() const { return fine_; }
  const DoseEstimates<Scalar>& estimates() const { return estimates_; }
  // The valve dead time the prediction uses: the datasheet's, or the measured one once it differs.
  Scalar dead_time_in_use_s_now() const { return effective_dead_s_; }
  // What the valve's feedback showed: the mean time from the command to the end position (closing
  // if seen, else opening) over `strokes` full strokes. The next dose's stroke is that less the dead
  // time in use, once it is clearly off the datasheet's.
  void measured_valve_travel(Scalar mean_s, std::uint32_t strokes) {
    measured_travel_s_ = mean_s;
    measured_travel_strokes_ = strokes;
  }
  Scalar stroke_in_use_s_now() const { return effective_stroke_s_; }

 private:
  Scalar prior_prediction_g() const;
  Scalar observed_prediction_g();
  Scalar fitted_prediction_g();
  void track_platform();
  void average_rate();
  void estimate_opening(Scalar net_weight_g);
  Scalar first_fall_height_m() const;
  void set_valve_timing(Scalar dead_s, Scalar stroke_s);
  Scalar stroke_in_use_s(Scalar dead_s) const;
  void learn_dead_time(Scalar measured_s);
  Scalar dead_time_in_use_s() const;

  model::CutoffGeometry<Scalar> geometry_;
  Scalar full_area_m2_ = Scalar(0);
  Scalar full_closing_flow_s_ = Scalar(0);
  Scalar half_closing_flow_s_ = Scalar(0);  // in seconds of half-open flow
  Scalar half_flow_ratio_ = Scalar(0.5);  // Beverloo: half-open flow / full flow
  Scalar half_transition_s_ = Scalar(0);  // dead time and half a stroke
  // From the close command until the valve is shut: dead time and the stroke still to travel.
  Scalar full_closing_duration_s_ = Scalar(0);
  Scalar half_closing_duration_s_ = Scalar(0);
  Scalar closing_duration_s_ = Scalar(0);
  Scalar jiffy_s_ = Scalar(0.01);
  Scalar prior_rate_kg_s_ = Scalar(0);
  Scalar opening_delay_s_ = Scalar(0);
  std::uint32_t settle_jiffies_ = 30;
  Scalar impact_threshold_g_ = Scalar(20);
  model::SlidingLineFit<Scalar, 128> fit_;
  model::RingingFlowObserver<Scalar> observer_;
  bool use_observer_ = true;
  Scalar platform_hz_ = Scalar(12);
  Scalar platform_kg_ = Scalar(4);
  std::uint32_t established_jiffies_ = 0;  // from the first grain until the stream is whole
  std::uint32_t measure_jiffy_ = 0;
  Scalar previous_sample_g_ = Scalar(0);
  Scalar last_impact_speed_m_s_ = Scalar(0);
  model::OpeningEstimator<Scalar> opening_{model::PlatformResponse<Scalar>{}};
  Scalar ramp_delay_s_ = Scalar(0);  // the landed mass's line starts this long after the first grain
  DoseEstimates<Scalar> estimates_{};
  model::BeverlooMaterial<Scalar> material_{};
  Scalar bore_m_ = Scalar(0);
  Scalar stroke_s_ = Scalar(0);          // the datasheet's
  Scalar effective_stroke_s_ = Scalar(0);  // the one this dose's timing uses
  Scalar measured_travel_s_ = Scalar(0);
  std::uint32_t measured_travel_strokes_ = 0;
  Scalar configured_dead_s_ = Scalar(0);
  Scalar measured_dead_s_ = Scalar(0);   // running mean over the last doses' first impacts
  Scalar effective_dead_s_ = Scalar(0);  // the one this dose's timing uses
  std::uint32_t dead_time_doses_ = 0;
  bool stream_confirmed_ = false;  // this dose's stream has run measurably: its dead time counts
  bool rate_change_pending_ = false;
  Scalar mean_rate_g_per_jiffy_ = Scalar(0);
  Scalar mean_window_jiffies_ = Scalar(100);

  Scalar start_weight_g_ = Scalar(0);
  std::uint32_t jiffies_ = 0;
  std::uint32_t impact_jiffy_ = 0;
  bool impacted_ = false;
  Scalar growth_per_jiffy_g_ = Scalar(0);
  Scalar last_fall_time_s_ = Scalar(0);
  Scalar last_fall_height_m_ = Scalar(0);
  bool fine_ = false;
  Scalar predicted_at_switch_g_ = Scalar(0);
  Scalar measured_full_rate_g_per_jiffy_ = Scalar(0);
  std::uint32_t switch_jiffy_ = 0;
};

using ModelCutoff = BasicModelCutoff<float>;

extern template class BasicModelCutoff<float>;
extern template class BasicModelCutoff<double>;

}  // namespace dynweigh::firmware
