#include "dynweigh/firmware/model_cutoff.hpp"

#include <cmath>

#include "dynweigh/model/bore_area.hpp"
#include "dynweigh/model/valve_let_through.hpp"

namespace dynweigh::firmware {
namespace {
template <typename Scalar>
constexpr Scalar kGravity = Scalar(9.81);
// The material is unknown until it flows: Beverloo's constants for a typical free-flowing sand
// (shared/PHYSICS.md §3) give the prior; the measured flow replaces it after the first impact.
template <typename Scalar>
constexpr model::BeverlooMaterial<Scalar> prior_material(Scalar bulk_density) {
  return {Scalar(0.58), Scalar(1.5), Scalar(0.0005), bulk_density};
}
}  // namespace

template <typename Scalar>
void BasicModelCutoff<Scalar>::configure(const Parameters& p) {
  const Scalar g = kGravity<Scalar>;
  const auto get = [&p](ParameterId id) { return Scalar(p.get(id)); };
  jiffy_s_ = get(ParameterId::jiffy_ms) / Scalar(1000);
  const Scalar bore_m = get(ParameterId::bore_mm) / Scalar(1000);
  const Scalar density = get(ParameterId::density);
  const Scalar dead_s = get(ParameterId::valve_dead_ms) / Scalar(1000);
  const Scalar stroke_s = get(ParameterId::valve_stroke_ms) / Scalar(1000);
  const auto material = prior_material(density);

  geometry_.g = g;
  geometry_.bore_area_m2 = model::bore_area_m2(bore_m);
  geometry_.bulk_density = density;
  geometry_.orifice_to_floor_m = get(ParameterId::fall_mm) / Scalar(1000);
  geometry_.pile.container_diameter_m = get(ParameterId::container_mm) / Scalar(1000);
  geometry_.pile.repose_angle_rad = get(ParameterId::repose_deg) * Scalar(M_PI) / Scalar(180);
  geometry_.pile.bulk_density = density;
  geometry_.pile_grows = p.get(ParameterId::pile_rise) > 0.5f;
  geometry_.closing_flow_seconds = model::closing_flow_seconds(material, g, bore_m, dead_s, stroke_s);
  full_area_m2_ = geometry_.bore_area_m2;
  full_closing_flow_s_ = geometry_.closing_flow_seconds;
  const Scalar full_rate = model::discharge_at_stroke_kg_s(material, g, bore_m, Scalar(1));
  const Scalar half_rate = model::discharge_at_stroke_kg_s(material, g, bore_m, Scalar(0.5));
  half_flow_ratio_ = full_rate > Scalar(0) ? half_rate / full_rate : Scalar(0.5);
  half_closing_flow_s_ =
      half_rate > Scalar(0)
          ? model::closing_flow_seconds(material, g, bore_m, dead_s, stroke_s, Scalar(0.5)) * full_rate / half_rate
          : dead_s;
  half_transition_s_ = dead_s + Scalar(0.25) * stroke_s;
  full_closing_duration_s_ = dead_s + stroke_s;
  half_closing_duration_s_ = dead_s + Scalar(0.5) * stroke_s;
  closing_duration_s_ = full_closing_duration_s_;

  prior_rate_kg_s_ = model::beverloo_discharge_kg_s(material, g, bore_m);
  // Opening mirrors closing: the flow that is missing at the start equals the let-through at the end.
  opening_delay_s_ = dead_s + stroke_s - (geometry_.closing_flow_seconds - dead_s);
  settle_jiffies_ = std::uint32_t(p.get(ParameterId::impact_settle_ms) / p.get(ParameterId::jiffy_ms));
  fit_.set_window(std::size_t(p.get(ParameterId::model_window_ms) / p.get(ParameterId::jiffy_ms)));
  // 20 d, or what the prior flow brings in two jiffies if that is more: a clear sign of flow.
  impact_threshold_g_ = std::fmax(Scalar(20), Scalar(2000) * prior_rate_kg_s_ * jiffy_s_);
}

template <typename Scalar>
void BasicModelCutoff<Scalar>::start(Scalar start_weight_g) {
  start_weight_g_ = start_weight_g;
  jiffies_ = 0;
  impacted_ = false;
  fine_ = false;
  geometry_.bore_area_m2 = full_area_m2_;
  geometry_.closing_flow_seconds = full_closing_flow_s_;
  closing_duration_s_ = full_closing_duration_s_;
  fit_.reset();
  growth_per_jiffy_g_ = prior_rate_kg_s_ * Scalar(1000) * jiffy_s_;
  last_fall_height_m_ = geometry_.orifice_to_floor_m;
  last_fall_time_s_ = model::fall_time(Scalar(0), kGravity<Scalar>, last_fall_height_m_);
}

template <typename Scalar>
void BasicModelCutoff<Scalar>::switch_to_half(Scalar predicted_now_g) {
  fine_ = true;
  predicted_at_switch_g_ = predicted_now_g;
  measured_full_rate_g_per_jiffy_ = growth_per_jiffy_g_;
  switch_jiffy_ = jiffies_;
  geometry_.bore_area_m2 = full_area_m2_ * model::open_area_fraction(Scalar(0.5));
  geometry_.closing_flow_seconds = half_closing_flow_s_;
  closing_duration_s_ = half_closing_duration_s_;
  growth_per_jiffy_g_ *= half_flow_ratio_;
  fit_.reset();
  // The half-open stream lands a fall time after the valve has moved; fitting starts after that
  // and the impact's settling, like at the first impact.
  impact_jiffy_ = jiffies_ + std::uint32_t(std::ceil((half_transition_s_ + last_fall_time_s_) / jiffy_s_));
}

template <typename Scalar>
Scalar BasicModelCutoff<Scalar>::prior_prediction_g() const {
  if (fine_) {
    const Scalar since_switch = Scalar(jiffies_ - switch_jiffy_);
    return predicted_at_switch_g_ + since_switch * measured_full_rate_g_per_jiffy_ * half_flow_ratio_;
  }
  // The sample of the n-th jiffy shows n - 1 jiffies of the valve's being open.
  const Scalar open_s = Scalar(jiffies_ - 1) * jiffy_s_;
  const Scalar flowing_s = std::fmax(Scalar(0), open_s - opening_delay_s_);
  return Scalar(1000) * prior_rate_kg_s_ * (flowing_s + geometry_.closing_flow_seconds);
}

template <typename Scalar>
Scalar BasicModelCutoff<Scalar>::observe(Scalar net_weight_g) {
  ++jiffies_;
  if (!impacted_ && net_weight_g - start_weight_g_ >= impact_threshold_g_) {
    impacted_ = true;
    impact_jiffy_ = jiffies_;
  }
  if (impacted_ && jiffies_ > impact_jiffy_ + settle_jiffies_) fit_.push(net_weight_g);
  if (!measuring()) return prior_prediction_g();

  const auto line = fit_.fit();
  const Scalar rate_kg_s = line.slope_per_sample / (Scalar(1000) * jiffy_s_);
  const auto prediction = model::predict_final(geometry_, line.value_at_newest / Scalar(1000), rate_kg_s);
  growth_per_jiffy_g_ = line.slope_per_sample;
  last_fall_time_s_ = prediction.fall_time_s;
  last_fall_height_m_ = prediction.fall_height_m;
  return (line.value_at_newest - start_weight_g_) + Scalar(1000) * prediction.above_reading_kg;
}

template <typename Scalar>
Scalar BasicModelCutoff<Scalar>::fall_height_m(Scalar net_weight_g) const {
  return model::fall_height_to_pile_m(geometry_.pile, geometry_.orifice_to_floor_m, net_weight_g / Scalar(1000));
}

template <typename Scalar>
Scalar BasicModelCutoff<Scalar>::settle_delay_s() const {
  // The let-through in seconds of full flow is shorter than the time it takes: a slow stroke lets the
  // last grains go late. Those fall from the orifice at almost no speed.
  return closing_duration_s_ + model::fall_time(Scalar(0), kGravity<Scalar>, last_fall_height_m_);
}

template class BasicModelCutoff<float>;
template class BasicModelCutoff<double>;

}  // namespace dynweigh::firmware
