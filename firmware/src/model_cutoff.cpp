#include "dynweigh/firmware/model_cutoff.hpp"

#include <cmath>

namespace dynweigh::firmware {
namespace {
template <typename Scalar>
constexpr Scalar kSmallestOpening = Scalar(0.25);  // of the stroke
// How far the open-time law is trusted beyond the longest open time it was taught at. Below a full
// stroke and the flow's start-up the fill grows faster than linearly with the open time, so a law
// taught on short closes, carried further, predicts too little and the close comes late: an
// overdose no top-up can take back. Closed at its reach, the fill ends short, a top-up finishes it,
// and the law is taught a longer open time for the next fill.
template <typename Scalar>
constexpr Scalar kLawReach = Scalar(1.5);
template <typename Scalar>
constexpr Scalar kLawReachS = Scalar(0.05);
// The material is unknown until it flows: Beverloo's constants for a typical free-flowing sand
// (docs/physics.md, Beverloo) give the prior; the measured flow replaces it after the first impact.
template <typename Scalar>
FinalWeightPredictorConfig<Scalar> predictor_config(const Parameters& p) {
  const auto get = [&p](ParameterId id) { return Scalar(p.get(id)); };
  FinalWeightPredictorConfig<Scalar> c;
  c.jiffy_s = get(ParameterId::jiffy_ms) / Scalar(1000);
  c.bore_m = get(ParameterId::bore_mm) / Scalar(1000);
  c.material = {Scalar(0.58), Scalar(1.5), Scalar(0.0005), get(ParameterId::density)};
  c.orifice_to_floor_m = get(ParameterId::fall_mm) / Scalar(1000);
  c.container_diameter_m = get(ParameterId::container_mm) / Scalar(1000);
  c.repose_angle_rad = get(ParameterId::repose_deg) * Scalar(M_PI) / Scalar(180);
  c.pile_grows = p.get(ParameterId::pile_rise) > 0.5f;
  return c;
}

template <typename Scalar>
ValveDatasheet<Scalar> valve_datasheet(const Parameters& p) {
  return {Scalar(p.get(ParameterId::valve_dead_ms)) / Scalar(1000), Scalar(p.get(ParameterId::valve_stroke_ms)) / Scalar(1000)};
}
}  // namespace

template <typename Scalar>
void BasicModelCutoff<Scalar>::configure(const Parameters& p) {
  const auto config = predictor_config<Scalar>(p);
  jiffy_s_ = config.jiffy_s;
  valve_.configure(valve_datasheet<Scalar>(p), config.material, config.bore_m);
  predictor_.configure(config);
  predictor_.use_valve_timing(valve_.in_use());
  estimator_.configure(p, predictor_.prior_rate_kg_s(), predictor_.full_open_geometry());
  const DoseValveTiming<Scalar>& timing = valve_.in_use();
  law_.configure(float(Scalar(1000) * predictor_.prior_rate_kg_s()),
                 float(timing.opening_delay_s - timing.full_closing_flow_s));
}

template <typename Scalar>
void BasicModelCutoff<Scalar>::start(Scalar start_weight_g, Scalar target_g) {
  valve_.start_dose();
  predictor_.start(start_weight_g, valve_.in_use());
  estimator_.start(start_weight_g, valve_.in_use());
  target_open_s_ = Scalar(law_.knows_open_time_law() ? law_.open_s_for(float(target_g)) : 0.0f);
  near_target_ = DoseHistory::PowerLaw{};
  curve_fitted_ = false;
  timed_by_law_ = false;
  timed_by_curve_ = false;
  model_prediction_g_ = Scalar(0);
  close_ = CloseRecord{};
}

template <typename Scalar>
Scalar BasicModelCutoff<Scalar>::observe(Scalar net_weight_g) {
  estimator_.time_opening(net_weight_g);
  if (estimator_.confirm_stream()) valve_.learn_dead_time(estimator_.estimates().dead_time_s);
  estimator_.track_flow(net_weight_g, predictor_.impact_speed_m_s());
  timed_by_law_ = !estimator_.measuring() && !predictor_.fine_feeding() && law_.knows_open_time_law();
  if (timed_by_law_) {
    // The kept doses' curve is fitted once, from the dose's second jiffy on: not in its first, whose
    // step already works out the valve's timing (no close comes that early).
    if (!curve_fitted_ && estimator_.jiffies() >= kCurveFitJiffy) {
      near_target_ = law_.learned().doses.near(float(target_open_s_));
      curve_fitted_ = true;
    }
    // The larger of the line and the kept doses' curve: the line falls short where the fill grows
    // faster than the open time (dose_history.hpp).
    const float line_g = law_.final_at_open_g(float(open_s())), curve_g = near_target_.fill_g(float(open_s()));
    timed_by_curve_ = curve_g > line_g;
    model_prediction_g_ = Scalar(timed_by_curve_ ? curve_g : line_g);
    return model_prediction_g_;
  }
  if (!estimator_.measuring()) {
    model_prediction_g_ = predictor_.from_prior(estimator_.jiffies(), valve_.gate_flow_shape());
    return model_prediction_g_;
  }
  if (!estimator_.uses_observer()) {
    model_prediction_g_ = predictor_.from_line(estimator_.line().value_at_newest, estimator_.line().slope_per_sample);
  } else {
    model_prediction_g_ = predictor_.from_observer(estimator_.equilibrium_g(), estimator_.rate_g_per_jiffy(),
                                                   estimator_.mean_rate_g_per_jiffy());
  }
  if (predictor_.fine_feeding()) return model_prediction_g_;
  const Scalar residual_s = Scalar(law_.close_residual_s(float(valve_.in_use().full_closing_flow_s)));
  model_prediction_g_ += residual_s * predictor_.growth_per_jiffy_g() / jiffy_s_;
  return model_prediction_g_;
}

template <typename Scalar>
Scalar BasicModelCutoff<Scalar>::growth_per_jiffy_g() const {
  if (!timed_by_law_ && !estimator_.measuring()) {
    return predictor_.prior_growth_per_jiffy_g(estimator_.jiffies(), valve_.gate_flow_shape());
  }
  if (!timed_by_law_) return predictor_.growth_per_jiffy_g();
  const float line_g_s = law_.law_flow_g_s();
  // The curve's prediction is the one observe() returned: its growth follows from it.
  const float curve_g_s =
      timed_by_curve_ ? near_target_.growth_g_per_s(float(open_s()), float(model_prediction_g_)) : 0.0f;
  return Scalar(curve_g_s > line_g_s ? curve_g_s : line_g_s) * jiffy_s_;
}

template <typename Scalar>
void BasicModelCutoff<Scalar>::learn(Scalar final_g, float close_sigma_g) {
  law_.learn(close_, float(final_g), close_sigma_g);
}

template <typename Scalar>
Scalar BasicModelCutoff<Scalar>::earliest_close_fraction() const {
  const DoseValveTiming<Scalar>& t = valve_.in_use();
  const Scalar earliest_s = t.dead_s + kSmallestOpening<Scalar> * t.stroke_s;
  return earliest_s / jiffy_s_ - Scalar(estimator_.jiffies() - 1);
}

template <typename Scalar>
bool BasicModelCutoff<Scalar>::beyond_the_law() const {
  const Scalar longest_s = Scalar(law_.longest_open_s());
  return timed_by_law_ && longest_s > Scalar(0) && open_s() + jiffy_s_ > kLawReach<Scalar> * longest_s + kLawReachS<Scalar>;
}

template <typename Scalar>
void BasicModelCutoff<Scalar>::closed(Scalar fraction) {
  const Scalar growth = growth_per_jiffy_g();
  close_.valid = true;
  close_.from_full_open = !predictor_.fine_feeding();
  close_.measured = estimator_.measuring() && !timed_by_law_;
  close_.open_s = float((Scalar(estimator_.jiffies() - 1) + fraction) * jiffy_s_);
  close_.prediction_g = float(model_prediction_g_ + fraction * growth);
  close_.flow_g_s = float(growth / jiffy_s_);
  const float in_use_s = float(valve_.in_use().full_closing_flow_s);
  close_.let_through_s = in_use_s + (close_.measured ? law_.close_residual_s(in_use_s) : 0.0f);
}

template <typename Scalar>
void BasicModelCutoff<Scalar>::switch_to_half(Scalar predicted_now_g) {
  predictor_.switch_to_half(predicted_now_g, estimator_.jiffies());
  estimator_.expect_half_stream(predictor_.half_stream_landing_s(), predictor_.growth_per_jiffy_g());
}

template <typename Scalar>
Scalar BasicModelCutoff<Scalar>::measured_flow_kg_s() const {
  return predictor_.growth_per_jiffy_g() / (Scalar(1000) * jiffy_s_);
}

template class BasicModelCutoff<float>;
template class BasicModelCutoff<double>;

}  // namespace dynweigh::firmware
