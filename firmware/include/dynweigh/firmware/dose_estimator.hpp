#pragma once
// What the model strategy estimates online during a dose, from the unfiltered weight alone: the
// first impact, timed within the jiffy, and the valve's dead time it implies; the static mass and
// the landing rate, by a Kalman observer that follows the platform's ringing (no filter lag), or by
// a line fitted to the weight once the ringing has calmed (`model_estimator line`); the mean flow;
// and, once the stream has run a while, the impulse its impact brings.
#include <cstdint>

#include "dynweigh/firmware/learned_valve_timing.hpp"
#include "dynweigh/firmware/parameters.hpp"
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
  Scalar flow_kg_s = 0;       // the mean landing rate at the last prediction at full open
  model::ImpactSignature<Scalar> signature{};
};

template <typename Scalar>
class BasicDoseEstimator {
 public:
  static constexpr std::uint32_t kMinimumFitSamples = 10;

  // `prior_rate_kg_s` is the flow expected before any is measured; `full_open` the plant's geometry
  // with the valve full open.
  void configure(const Parameters& parameters, Scalar prior_rate_kg_s, const model::CutoffGeometry<Scalar>& full_open);
  // At the open command: the scale's net grams and the valve's timing for this dose.
  void start(Scalar start_weight_g, const DoseValveTiming<Scalar>& timing);

  // One jiffy's unfiltered sample goes through these steps, in this order.
  // 1. Counts the jiffy and times the first impact until it is found.
  void time_opening(Scalar net_weight_g);
  // 2. True in the jiffy the stream is seen to run measurably, well after its impact: the dead time
  //    just timed tells of the valve, and the impact's signature is read.
  bool confirm_stream();
  // 3. Follows the static mass and the landing rate; `impact_speed_m_s` sets the platform's kick.
  void track_flow(Scalar net_weight_g, Scalar impact_speed_m_s);

  bool measuring() const {
    return use_observer_ ? observer_.started() && jiffies_ > measure_jiffy_ : fit_.count() >= kMinimumFitSamples;
  }
  bool uses_observer() const { return use_observer_; }
  std::uint32_t jiffies() const { return jiffies_; }  // since the open command
  // The observer's: the reading without the ringing, the landing rate now and its mean.
  Scalar equilibrium_g() const { return observer_.equilibrium_g(); }
  Scalar rate_g_per_jiffy() const { return observer_.rate_g_per_jiffy(); }
  Scalar mean_rate_g_per_jiffy() const { return mean_rate_g_per_jiffy_; }
  // The line's, once measuring.
  const typename model::SlidingLineFit<Scalar, 128>::Line& line() const { return line_; }

  // The valve goes to half: the half-open stream lands `landing_s` from now at about
  // `half_rate_g_per_jiffy`; the flow is measured again once it is whole.
  void expect_half_stream(Scalar landing_s, Scalar half_rate_g_per_jiffy);

  const DoseEstimates<Scalar>& estimates() const { return estimates_; }

 private:
  void start_observer(Scalar net_weight_g, Scalar previous_g);
  void track_platform(Scalar impact_speed_m_s);
  void average_rate();
  void record_flow();
  Scalar first_fall_height_m() const;

  model::CutoffGeometry<Scalar> full_open_{};
  Scalar jiffy_s_ = Scalar(0.01);
  Scalar prior_rate_kg_s_ = Scalar(0);
  Scalar prior_per_jiffy_g_ = Scalar(0);
  Scalar impact_threshold_g_ = Scalar(20);
  std::uint32_t settle_jiffies_ = 30;
  bool use_observer_ = true;
  Scalar platform_hz_ = Scalar(12);
  Scalar platform_kg_ = Scalar(4);
  Scalar mean_window_jiffies_ = Scalar(100);
  model::SlidingLineFit<Scalar, 128> fit_;
  typename model::SlidingLineFit<Scalar, 128>::Line line_{};
  model::RingingFlowObserver<Scalar> observer_;
  model::OpeningEstimator<Scalar> opening_{model::PlatformResponse<Scalar>{}};

  // This dose's.
  Scalar start_weight_g_ = Scalar(0);
  Scalar opening_delay_s_ = Scalar(0);
  Scalar ramp_delay_s_ = Scalar(0);
  std::uint32_t established_jiffies_ = 0;  // from the first grain until the stream is whole
  std::uint32_t jiffies_ = 0;
  Scalar previous_sample_g_ = Scalar(0);
  bool impacted_ = false;
  std::uint32_t impact_jiffy_ = 0;
  std::uint32_t measure_jiffy_ = 0;
  bool half_stream_ = false;
  bool rate_change_pending_ = false;
  Scalar expected_rate_g_per_jiffy_ = Scalar(0);
  bool stream_confirmed_ = false;  // this dose's stream has run measurably: its dead time counts
  Scalar mean_rate_g_per_jiffy_ = Scalar(0);
  DoseEstimates<Scalar> estimates_{};
};

extern template class BasicDoseEstimator<float>;
extern template class BasicDoseEstimator<double>;

}  // namespace dynweigh::firmware
