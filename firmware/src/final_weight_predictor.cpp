#include "dynweigh/firmware/final_weight_predictor.hpp"

#include "dynweigh/model/bore_area.hpp"
#include "dynweigh/model/gravity.hpp"
#include "dynweigh/model/ideal_model.hpp"

namespace dynweigh::firmware {

template <typename Scalar>
void BasicFinalWeightPredictor<Scalar>::configure(const FinalWeightPredictorConfig<Scalar>& c) {
  jiffy_s_ = c.jiffy_s;
  geometry_.g = model::kGravity<Scalar>;
  geometry_.bore_area_m2 = model::bore_area_m2(c.bore_m);
  geometry_.bulk_density = c.material.bulk_density;
  geometry_.orifice_to_floor_m = c.orifice_to_floor_m;
  geometry_.pile.container_diameter_m = c.container_diameter_m;
  geometry_.pile.repose_angle_rad = c.repose_angle_rad;
  geometry_.pile.bulk_density = c.material.bulk_density;
  geometry_.pile_grows = c.pile_grows;
  full_area_m2_ = geometry_.bore_area_m2;
  prior_rate_kg_s_ = model::beverloo_discharge_kg_s(c.material, model::kGravity<Scalar>, c.bore_m);
}

template <typename Scalar>
void BasicFinalWeightPredictor<Scalar>::use_valve_timing(const DoseValveTiming<Scalar>& timing) {
  timing_ = timing;
  geometry_.closing_flow_seconds = timing.full_closing_flow_s;
  closing_duration_s_ = timing.full_closing_duration_s;
}

template <typename Scalar>
void BasicFinalWeightPredictor<Scalar>::start(Scalar start_weight_g, const DoseValveTiming<Scalar>& timing) {
  use_valve_timing(timing);
  start_weight_g_ = start_weight_g;
  fine_ = false;
  geometry_.bore_area_m2 = full_area_m2_;
  growth_per_jiffy_g_ = prior_rate_kg_s_ * Scalar(1000) * jiffy_s_;
  last_fall_height_m_ = geometry_.orifice_to_floor_m;
  last_fall_time_s_ = model::fall_time(Scalar(0), model::kGravity<Scalar>, last_fall_height_m_);
  const Scalar prior_v0 = model::outflow_speed(prior_rate_kg_s_, full_area_m2_, geometry_.bulk_density);
  last_impact_speed_m_s_ = model::impact_speed(prior_v0, model::kGravity<Scalar>, last_fall_height_m_);
}

template <typename Scalar>
Scalar BasicFinalWeightPredictor<Scalar>::stroke_reached(Scalar open_s) const {
  // The gate starts and stops moving one dead time after its commands: a close at `open_s` stops it
  // at open_s / stroke of the way.
  return timing_.stroke_s > open_s ? open_s / timing_.stroke_s : Scalar(1);
}

template <typename Scalar>
Scalar BasicFinalWeightPredictor<Scalar>::from_prior(std::uint32_t jiffies,
                                                     const model::GateFlowShape<Scalar>& shape) const {
  if (fine_) {
    const Scalar since_switch = Scalar(jiffies - switch_jiffy_);
    return predicted_at_switch_g_ + since_switch * measured_full_rate_g_per_jiffy_ * timing_.half_flow_ratio;
  }
  // The sample of the n-th jiffy shows n - 1 jiffies of the valve's being open.
  const Scalar open_s = Scalar(jiffies - 1) * jiffy_s_;
  const Scalar full_flow_g_s = Scalar(1000) * prior_rate_kg_s_;
  const Scalar reached = stroke_reached(open_s);
  if (reached < Scalar(1)) return full_flow_g_s * shape.ramps_seconds(reached, timing_.stroke_s);
  const Scalar flowing_s = std::fmax(Scalar(0), open_s - timing_.opening_delay_s);
  return full_flow_g_s * (flowing_s + geometry_.closing_flow_seconds);
}

template <typename Scalar>
Scalar BasicFinalWeightPredictor<Scalar>::prior_growth_per_jiffy_g(std::uint32_t jiffies,
                                                                   const model::GateFlowShape<Scalar>& shape) const {
  if (fine_) return growth_per_jiffy_g_;
  const Scalar reached = stroke_reached(Scalar(jiffies - 1) * jiffy_s_);
  const Scalar full_g_per_jiffy = Scalar(1000) * prior_rate_kg_s_ * jiffy_s_;
  return reached < Scalar(1) ? Scalar(2) * shape.flow_at(reached) * full_g_per_jiffy : full_g_per_jiffy;
}

template <typename Scalar>
Scalar BasicFinalWeightPredictor<Scalar>::from_observer(Scalar equilibrium_g, Scalar rate_g_per_jiffy,
                                                        Scalar mean_rate_g_per_jiffy) {
  const Scalar per_g_per_jiffy = Scalar(1) / (Scalar(1000) * jiffy_s_);
  const auto prediction = model::predict_final(geometry_, equilibrium_g / Scalar(1000),
                                               rate_g_per_jiffy * per_g_per_jiffy,
                                               mean_rate_g_per_jiffy * per_g_per_jiffy);
  growth_per_jiffy_g_ = rate_g_per_jiffy;
  last_fall_time_s_ = prediction.fall_time_s;
  last_fall_height_m_ = prediction.fall_height_m;
  last_impact_speed_m_s_ = model::impact_speed(prediction.outflow_speed_m_s, model::kGravity<Scalar>, prediction.fall_height_m);
  return (equilibrium_g - start_weight_g_) + Scalar(1000) * prediction.above_reading_kg;
}

template <typename Scalar>
Scalar BasicFinalWeightPredictor<Scalar>::from_line(Scalar value_at_newest_g, Scalar slope_g_per_jiffy) {
  const Scalar rate_kg_s = slope_g_per_jiffy / (Scalar(1000) * jiffy_s_);
  const auto prediction = model::predict_final(geometry_, value_at_newest_g / Scalar(1000), rate_kg_s);
  growth_per_jiffy_g_ = slope_g_per_jiffy;
  last_fall_time_s_ = prediction.fall_time_s;
  last_fall_height_m_ = prediction.fall_height_m;
  return (value_at_newest_g - start_weight_g_) + Scalar(1000) * prediction.above_reading_kg;
}

// The flow, the open area and the let-through change. Until the valve reaches half the flow is
// still (about) full; from half open the valve lets less through than from full.
template <typename Scalar>
void BasicFinalWeightPredictor<Scalar>::switch_to_half(Scalar predicted_now_g, std::uint32_t jiffies) {
  fine_ = true;
  measured_full_rate_g_per_jiffy_ = growth_per_jiffy_g_;
  const Scalar full_per_s = measured_full_rate_g_per_jiffy_ / jiffy_s_;
  const Scalar half_per_s = full_per_s * timing_.half_flow_ratio;
  predicted_at_switch_g_ = predicted_now_g - full_per_s * timing_.full_closing_flow_s +
                           half_per_s * timing_.half_closing_flow_s +
                           (full_per_s - half_per_s) * timing_.half_transition_s;
  switch_jiffy_ = jiffies;
  geometry_.bore_area_m2 = full_area_m2_ * model::open_area_fraction(Scalar(0.5));
  geometry_.closing_flow_seconds = timing_.half_closing_flow_s;
  closing_duration_s_ = timing_.half_closing_duration_s;
  growth_per_jiffy_g_ *= timing_.half_flow_ratio;
}

template <typename Scalar>
Scalar BasicFinalWeightPredictor<Scalar>::fall_height_m(Scalar net_weight_g) const {
  return model::fall_height_to_pile_m(geometry_.pile, geometry_.orifice_to_floor_m, net_weight_g / Scalar(1000));
}

template <typename Scalar>
Scalar BasicFinalWeightPredictor<Scalar>::settle_delay_s() const {
  // The let-through in seconds of full flow is shorter than the time it takes: a slow stroke lets the
  // last grains go late. Those fall from the orifice at almost no speed.
  return closing_duration_s_ + model::fall_time(Scalar(0), model::kGravity<Scalar>, last_fall_height_m_);
}

template class BasicFinalWeightPredictor<float>;
template class BasicFinalWeightPredictor<double>;

}  // namespace dynweigh::firmware
